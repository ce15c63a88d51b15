// core/sampler.h: per-sample random numbers. Values depend only on (pixel, sample index, seed, dimension),
// never on threads or scheduling, so an image is bit-identical for any thread count.
#pragma once

#include "core/math.h"
#include "core/rng.h"

namespace pv {

enum class SamplerKind : uint8_t { Independent };

class Sampler {
public:
    explicit Sampler(uint32_t seed = 0) : m_seed(seed) {}

    // Begins sample `index` of `pixel`; dimensions restart at 0.
    void start(uvec2 pixel, uint32_t index) {
        const uint64_t key = hash_combine(hash_combine(hash_combine(0x70617468ull, m_seed), pixel.x), pixel.y);
        m_rng.seed(hash_combine(key, index), key);
    }
    float get1d() { return m_rng.next_float(); }
    vec2 get2d() {
        const float a = m_rng.next_float();
        return vec2(a, m_rng.next_float());
    }

private:
    uint32_t m_seed;
    Pcg32 m_rng;
};

}  // namespace pv
