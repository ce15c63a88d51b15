// core/sampling/rng.h: PCG32 (O'Neill 2014) and integer hashes. Uniform floats are in [0, 1), never 1.0.
#pragma once

#include <cstdint>

namespace pv {

// SplitMix64's finaliser (Steele et al. 2014): a strong 64-bit mixer used to derive independent streams.
inline uint64_t mix64(uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return x;
}

inline uint64_t hash_combine(uint64_t seed, uint64_t v) { return mix64(seed ^ (v + 0x9e3779b97f4a7c15ull)); }

class Pcg32 {
public:
    Pcg32() = default;
    Pcg32(uint64_t init_state, uint64_t stream) { seed(init_state, stream); }

    void seed(uint64_t init_state, uint64_t stream) {
        m_state = 0;
        m_inc = (stream << 1u) | 1u;
        next_u32();
        m_state += init_state;
        next_u32();
    }
    uint32_t next_u32() {
        const uint64_t old = m_state;
        m_state = old * 0x5851f42d4c957f2dull + m_inc;
        const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
    }
    // 24 random mantissa bits: exactly representable, so the result is at most 1 - 2^-24.
    float next_float() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }

private:
    uint64_t m_state = 0x853c49e6748fea9bull;
    uint64_t m_inc = 0xda3e39cb94b95bdbull;
};

}  // namespace pv
