// core/sampling/sampler.h: per-sample random numbers. Values depend only on (pixel, sample index, seed, dimension),
// never on threads or scheduling, so an image is bit-identical for any thread count.
#pragma once

#include <optional>
#include <string>

#include "core/base/math.h"
#include "core/base/text.h"
#include "core/sampling/rng.h"
#include "core/sampling/sobol.h"

namespace pv {

// The sampler's two kinds:
//   independent: PCG32 keyed on (pixel, index, seed); error falls as 1/spp.
//   sobol: shuffled, Owen-scrambled Sobol padded per draw (core/sampling/sobol.h), as two independent nets per pixel:
//          the even samples 0, 2, 4, ... are points 0, 1, 2, ... of one scrambled sequence and the odd samples those
//          of another, keyed on (pixel, index & 1). Each half's first 2^m samples are stratified like a (0,m,2)-net,
//          and the halves are independent estimators, which the film's even/odd error estimate needs (one net
//          over all samples would make 2k and 2k+1 an antithetic pair: the estimate would be too high, its slope
//          stuck near -1). Use power-of-two spp to get its full benefit.
enum class SamplerKind : uint8_t { Independent, Sobol };

// --sampler's words (and the settings text's): "independent" or "sobol" (also "ind").
inline constexpr NamedValue<SamplerKind> kSamplerNames[] = {
    {"independent", SamplerKind::Independent}, {"ind", SamplerKind::Independent}, {"sobol", SamplerKind::Sobol}};
inline const char* sampler_name(SamplerKind k) { return name_of(kSamplerNames, k); }
// "independent" or "sobol" (also "ind"); nothing for anything else.
inline std::optional<SamplerKind> parse_sampler(const std::string& s) { return value_of(kSamplerNames, s); }

class Sampler {
public:
    explicit Sampler(uint32_t seed = 0, SamplerKind kind = SamplerKind::Independent)
        : m_kind(kind), m_seed_key(hash_combine(0x70617468ull, seed)) {}

    // Begins sample `index` of `pixel`; dimensions restart at 0.
    void start(uvec2 pixel, uint32_t index) {
        const uint64_t key = hash_combine(hash_combine(m_seed_key, pixel.x), pixel.y);
        if (m_kind == SamplerKind::Independent) {
            m_rng.seed(hash_combine(key, index), key);
        } else {
            m_key = hash_combine(key, index & 1u);
            m_rindex = reverse_bits32(index >> 1);
        }
        m_dim = 0;
    }
    // The next dimension(s), in order.
    float get1d() { return get1d_at(m_dim++); }
    vec2 get2d() { return get2d_at(m_dim++); }

    // Reserves `n` consecutive dimensions and returns the first; get*_at(first + k) then draws dimension k of the
    // block when (and only when) the caller needs it. Each dimension keeps its meaning in every sample of a pixel,
    // which the Sobol sampler's stratification needs, while skipped draws cost nothing. (The independent sampler
    // ignores the dimension and takes the next values of its stream.)
    uint32_t reserve(uint32_t n) {
        const uint32_t first = m_dim;
        m_dim += n;
        return first;
    }
    [[gnu::always_inline]] float get1d_at(uint32_t dim) {
        if (m_kind == SamplerKind::Independent) return m_rng.next_float();
        return sobol_owen_1d_rev(m_rindex, draw_seed(dim));
    }
    [[gnu::always_inline]] vec2 get2d_at(uint32_t dim) {
        if (m_kind == SamplerKind::Independent) {
            const float a = m_rng.next_float();
            return vec2(a, m_rng.next_float());
        }
        return sobol_owen_2d_rev(m_rindex, draw_seed(dim));
    }
    SamplerKind kind() const { return m_kind; }

private:
    // Padding: every draw gets its own shuffle and scramble seeds, so draws are decorrelated (Burley 2020, sec. 4).
    uint64_t draw_seed(uint32_t dim) const { return hash_combine(m_key, dim); }

    SamplerKind m_kind;
    uint64_t m_seed_key;  // hash of the seed, shared by all pixels
    Pcg32 m_rng;
    uint64_t m_key = 0;
    uint32_t m_rindex = 0;  // the sample index, bit-reversed once per sample
    uint32_t m_dim = 0;
};

}  // namespace pv
