// core/adaptive.h: where and how long to sample. Adaptive sampling: after a pass, each pixel's relative error is
// estimated from the film's two half buffers (pixel_rel_mse: relative to mean^2 + 0.01, as the metrics); its
// per-sample relative variance (that times the pixel's count) is averaged over a (2r+1)^2 neighbourhood, because one
// pixel's estimate has only about 3 degrees of freedom, and divided by the pixel's count again; a pixel whose
// filtered relative RMS error is below the noise threshold takes no more samples. Pixels are judged only at the
// checkpoint counts 2^k and 3 x 2^(k-1): a geometric schedule, so a pixel is looked at O(log n) times (each look is
// a chance to stop on an estimate that happens to be low: the bias of stopping on the samples themselves).
// Everything here depends only on the film and the counts, so images stay identical for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "core/film.h"

namespace pv {

struct AdaptiveSettings {
    float noise_threshold = 0.f;  // relative RMS error below which a pixel stops (e.g. 0.02); 0: off
    uint32_t min_spp = 16;        // no pixel stops before this many samples
    int radius = 2;               // the error is averaged over (2 radius + 1)^2 pixels

    bool enabled() const { return noise_threshold > 0.f; }
    bool operator==(const AdaptiveSettings& o) const {
        return noise_threshold == o.noise_threshold && min_spp == o.min_spp && radius == o.radius;
    }
    bool operator!=(const AdaptiveSettings& o) const { return !(*this == o); }
};

// True for the counts at which adaptive sampling judges pixels: 2^k and 3 x 2^(k-1) (1, 2, 3, 4, 6, 8, 12, 16, 24...).
bool is_adaptive_checkpoint(uint32_t n);

// The per-pixel active mask of adaptive sampling.
class AdaptiveMask {
public:
    // All width x height pixels active.
    void reset(int width, int height);
    // After pass number `spp` (1-based count of passes so far) has landed in `film`: on a checkpoint count >=
    // min_spp, pixels whose filtered error is below the threshold stop. A stopped pixel never restarts.
    void update(const Film& film, uint32_t spp, const AdaptiveSettings& settings);

    bool active(int x, int y) const { return m_active[size_t(y) * size_t(m_width) + size_t(x)] != 0; }
    const std::vector<uint8_t>& mask() const { return m_active; }
    size_t active_count() const { return m_active_count; }
    double active_fraction() const { return m_active.empty() ? 0.0 : double(m_active_count) / double(m_active.size()); }
    bool converged() const { return !m_active.empty() && m_active_count == 0; }
    // The largest filtered relative MSE among the pixels still active after the last update (0 before any).
    double worst_rel_mse() const { return m_worst; }

private:
    int m_width = 0, m_height = 0;
    std::vector<uint8_t> m_active;
    size_t m_active_count = 0;
    double m_worst = 0.0;
    std::vector<float> m_error, m_row;  // scratch: per-pixel and row-filtered relative MSE
};

}  // namespace pv
