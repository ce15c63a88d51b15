// core/sampler.h: per-sample random numbers. Values depend only on (pixel, sample index, seed, dimension),
// never on threads or scheduling, so an image is bit-identical for any thread count. Two kinds:
//   independent: PCG32 keyed on (pixel, index, seed); error falls as 1/spp.
//   sobol: shuffled, Owen-scrambled Sobol padded per draw (core/sobol.h); each 1D/2D draw of the first 2^m samples
//          of a pixel is stratified like a (0,m,2)-net. Use power-of-two spp to get its full benefit.
#pragma once

#include "core/math.h"
#include "core/rng.h"
#include "core/sobol.h"

#include <optional>
#include <string>

namespace pv {

enum class SamplerKind : uint8_t { Independent, Sobol };

inline const char* sampler_name(SamplerKind k) { return k == SamplerKind::Sobol ? "sobol" : "independent"; }
// "independent" or "sobol" (also "ind"); nothing for anything else.
inline std::optional<SamplerKind> parse_sampler(const std::string& s) {
    if (s == "independent" || s == "ind") return SamplerKind::Independent;
    if (s == "sobol") return SamplerKind::Sobol;
    return std::nullopt;
}

class Sampler {
public:
    explicit Sampler(uint32_t seed = 0, SamplerKind kind = SamplerKind::Independent) : m_seed(seed), m_kind(kind) {}

    // Begins sample `index` of `pixel`; dimensions restart at 0.
    void start(uvec2 pixel, uint32_t index) {
        const uint64_t key = hash_combine(hash_combine(hash_combine(0x70617468ull, m_seed), pixel.x), pixel.y);
        if (m_kind == SamplerKind::Independent) {
            m_rng.seed(hash_combine(key, index), key);
        } else {
            m_key = key;
            m_index = index;
            m_dim = 0;
        }
    }
    float get1d() {
        if (m_kind == SamplerKind::Independent) return m_rng.next_float();
        return sobol_owen_1d(m_index, next_draw_seed());
    }
    vec2 get2d() {
        if (m_kind == SamplerKind::Independent) {
            const float a = m_rng.next_float();
            return vec2(a, m_rng.next_float());
        }
        return sobol_owen_2d(m_index, next_draw_seed());
    }
    SamplerKind kind() const { return m_kind; }

private:
    // Padding: every draw gets its own shuffle and scramble seeds, so draws are decorrelated (Burley 2020, sec. 4).
    uint64_t next_draw_seed() { return hash_combine(m_key, m_dim++); }

    uint32_t m_seed;
    SamplerKind m_kind;
    Pcg32 m_rng;
    uint64_t m_key = 0;
    uint32_t m_index = 0;
    uint32_t m_dim = 0;
};

}  // namespace pv
