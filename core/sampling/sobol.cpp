// core/sampling/sobol.cpp: Sobol dimension 1 by byte tables of its generator matrix.
#include "core/sampling/sobol.h"

#include <array>

namespace pv {
namespace {

using Dim1Tables = std::array<std::array<uint32_t, 256>, 4>;

// Column k of dimension 1's generator matrix is the direction number v_k (Sobol 1967, primitive polynomial x + 1):
// v_0 = 2^31, v_{k+1} = v_k ^ (v_k >> 1), i.e. the rows of Pascal's triangle mod 2. The product with the index
// bits is an XOR of columns, done a byte at a time from four 256-entry tables (built at compile time).
constexpr Dim1Tables make_dim1_tables() {
    uint32_t v[32] = {};
    v[0] = 0x80000000u;
    for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
    Dim1Tables t{};
    for (int byte = 0; byte < 4; ++byte)
        for (uint32_t b = 0; b < 256; ++b) {
            uint32_t x = 0;
            for (int bit = 0; bit < 8; ++bit)
                if (b & (1u << bit)) x ^= v[byte * 8 + bit];
            t[size_t(byte)][b] = x;
        }
    return t;
}

constexpr Dim1Tables kDim1 = make_dim1_tables();

}  // namespace

uint32_t sobol_dim1(uint32_t index) {
    return kDim1[0][index & 0xffu] ^ kDim1[1][(index >> 8) & 0xffu] ^ kDim1[2][(index >> 16) & 0xffu] ^
           kDim1[3][index >> 24];
}

}  // namespace pv
