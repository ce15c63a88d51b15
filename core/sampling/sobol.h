// core/sampling/sobol.h: a shuffled, Owen-scrambled, padded Sobol sequence (Burley 2020, "Practical Hash-based Owen
// Scrambling", JCGT 9(4); pbrt-v4's PaddedSobolSampler with FastOwenScrambler). Each 1D or 2D draw of a sample has
// its own seed: the sample index is shuffled by a nested uniform scramble (which permutes every aligned block of 2^m
// indices, so the first 2^m samples of a pixel form a (0,m,2)-net in each 2D pair), then the point is Owen-scrambled.
#pragma once

#include <cstdint>

#include "core/base/math.h"

namespace pv {

// Byte swap, then the bits within each byte (three mask-and-shift steps instead of five).
inline uint32_t reverse_bits32(uint32_t v) {
    v = __builtin_bswap32(v);
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    return ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
}

// The hash of Burley 2020 sec. 3 (a Laine-Karras-style permutation), as in pbrt-v4's FastOwenScrambler: every step
// maps bit k to bit k XOR f(lower bits), so the map is a bijection whose bit k depends only on bits <= k.
inline uint32_t laine_karras_permutation(uint32_t v, uint32_t seed) {
    v ^= v * 0x3d20adeau;
    v += seed;
    v *= (seed >> 16) | 1u;
    v ^= v * 0x05526c56u;
    v ^= v * 0x53a22864u;
    return v;
}

// Nested uniform (Owen) scramble of a 0.32 fixed-point value: bit k (from the top) is flipped by a hash of the
// bits above it: the permutation applied to the bit-reversed word.
inline uint32_t owen_scramble(uint32_t v, uint32_t seed) {
    return reverse_bits32(laine_karras_permutation(reverse_bits32(v), seed));
}

// Sobol dimension 0 (van der Corput) and dimension 1 of sample `index`, as 0.32 fixed point. (The sampler uses
// sobol_dim1_reversed below; sobol_dim1's tables are the direct form it is tested against.)
inline uint32_t sobol_dim0(uint32_t index) { return reverse_bits32(index); }
uint32_t sobol_dim1(uint32_t index);

// 0.32 fixed point -> float in [0, 1): the top 24 bits are exact in a float, so values are in [0, 1), never 1.0.
inline float fixed_to_float(uint32_t v) { return static_cast<float>(v >> 8) * 0x1p-24f; }

// Dimension 1 with both its input and its output bit-reversed: reverse_bits32(sobol_dim1(i)) computed from i
// directly. Bit j of the reversed direction number v_b is binomial(b, j) mod 2, which by Lucas' theorem is 1
// exactly when the bits of j are a subset of those of b; so output bit j is the parity of the set index bits b
// that contain j: a superset-sum transform over the 5-bit positions, five shift-and-mask steps.
inline uint32_t sobol_dim1_reversed(uint32_t i) {
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0f0f0f0fu;
    i ^= (i >> 8) & 0x00ff00ffu;
    i ^= i >> 16;
    return i;
}

// One draw of the padded sequence. `seed` is a 64-bit hash of (pixel, seed, dimension): its parts seed the index
// shuffle and each coordinate's scramble. `rindex` is the sample index bit-reversed (the sampler reverses it once
// per sample rather than once per draw).
// The shuffled index is owen_scramble(index, s) = reverse(lk(reverse(index), s)) = reverse(lk(rindex, s)), and
// owen_scramble(sobol_dim0(i), s) = reverse(lk(reverse(reverse(i)), s)) = reverse(lk(i, s)): the inner pair of
// reversals cancels, so it is skipped (same values, fewer instructions).
inline uint32_t shuffled_index(uint32_t rindex, uint64_t seed) {
    return reverse_bits32(laine_karras_permutation(rindex, static_cast<uint32_t>(seed)));
}
inline float sobol_owen_1d_rev(uint32_t rindex, uint64_t seed) {
    const uint32_t i = shuffled_index(rindex, seed);
    return fixed_to_float(reverse_bits32(laine_karras_permutation(i, static_cast<uint32_t>(seed >> 32))));
}
inline vec2 sobol_owen_2d_rev(uint32_t rindex, uint64_t seed) {
    const uint32_t i = shuffled_index(rindex, seed);
    const uint32_t sx = static_cast<uint32_t>(seed >> 32);
    // A second, different 32-bit seed for y from the same hash (odd multiplier: a bijection of sx).
    const uint32_t sy = (sx ^ 0x9e3779b9u) * 0x85ebca6bu + 0x7f4a7c15u;
    // y = owen_scramble(sobol_dim1(i), sy) = reverse(lk(reverse(sobol_dim1(i)), sy)).
    return vec2(fixed_to_float(reverse_bits32(laine_karras_permutation(i, sx))),
                fixed_to_float(reverse_bits32(laine_karras_permutation(sobol_dim1_reversed(i), sy))));
}

}  // namespace pv
