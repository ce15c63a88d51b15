// core/adaptive.h: where and how long to sample. Adaptive sampling: after a pass, each pixel's relative error is
// estimated from the film's two half buffers (pixel_rel_mse: relative to mean^2 + 0.01, as the metrics); its
// per-sample relative variance (that times the pixel's count) is averaged over a (2r+1)^2 neighbourhood, because one
// pixel's estimate has only about 3 degrees of freedom, and divided by the pixel's count again; a pixel whose
// filtered relative RMS error is below the noise threshold takes no more samples. Pixels are judged only at the
// checkpoint counts 2^k and 3 x 2^(k-1): a geometric schedule, so a pixel is looked at O(log n) times (each look is
// a chance to stop on an estimate that happens to be low: the bias of stopping on the samples themselves).
// Everything here depends only on the film and the counts, so images stay identical for any thread count.
//
// Allocation (AdaptiveSettings::allocate, the command line's default): the mean relMSE at a fixed budget is lowest
// with each pixel's count n_i proportional to its relative standard deviation per sample r_i (minimise
// sum r_i^2 / n_i subject to sum n_i = N: n_i = N r_i / sum r_j; against uniform counts the relMSE falls by
// mean(r)^2 / mean(r^2)), whereas stopping at a threshold makes n_i proportional to r_i^2. At each checkpoint a
// pixel's weight is computed from the same 5x5-filtered per-sample estimate. A sample's cost c_i varies too (a
// path into a deep interior traces more rays than one that escapes), and with it the optimum, n_i proportional to
// r_i / sqrt(c_i); c_i is the pixel's rays per sample (deterministic, unlike time) plus one for the per-sample
// work, filtered the same way. w_i = s_i / s_ref with s_i = r_i / sqrt(c_i) and s_ref the kAllocationQuantile
// quantile of s over the image (a robust maximum), clamped to [kAllocationFloor, 1]; in
// pass P + 1 a pixel takes a sample while its count is below (P + 1) w_i, so after P passes it has about P w_i.
// Each pixel's samples take the indices 0, 1, 2... of its own count, so a pixel's sample set is the one a uniform
// render of that many passes would give it (Sobol's stratification holds per pixel). The weights come from the
// samples themselves, which biases the estimate slightly, like stopping (docs/convergence.md, part 2); the floor
// keeps every pixel converging.
#pragma once

#include <cstdint>
#include <vector>

#include "core/film.h"

namespace pv {

constexpr double kAllocationQuantile = 0.97;  // r_ref: this quantile of the pixels' relative error per sample
constexpr float kAllocationFloor = 0.25f;     // the least weight: a quarter of the noisiest pixels' rate

struct AdaptiveSettings {
    float noise_threshold = 0.f;  // relative RMS error below which a pixel stops (e.g. 0.02); 0: off
    uint32_t min_spp = 16;        // no pixel stops before this many samples
    int radius = 2;               // the error is averaged over (2 radius + 1)^2 pixels
    bool allocate = false;        // samples in proportion to each pixel's relative error per sample (see above)

    // The noise threshold: pixels stop, and a render ends once all have.
    bool enabled() const { return noise_threshold > 0.f; }
    // Some pixels may skip a pass (threshold or allocation).
    bool masks() const { return enabled() || allocate; }
    bool operator==(const AdaptiveSettings& o) const {
        return noise_threshold == o.noise_threshold && min_spp == o.min_spp && radius == o.radius &&
               allocate == o.allocate;
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
    // Allocation: before pass number `pass` (1-based), marks active the pixels not stopped whose count is below
    // pass x weight. Without allocation, nothing changes.
    void prepare_pass(uint32_t pass, const AdaptiveSettings& settings);
    // With allocation, each pixel's next sample index (its count of samples taken); the pass's worker that owns the
    // pixel advances it.
    uint32_t& next_index(int x, int y) { return m_next[size_t(y) * size_t(m_width) + size_t(x)]; }
    // With allocation, the rays a sample of pixel (x, y) traced: the cost side of the weights.
    void add_rays(int x, int y, uint64_t rays) { m_rays[size_t(y) * size_t(m_width) + size_t(x)] += rays; }
    // The allocation weight of pixel (x, y) (1 before the first checkpoint or without allocation).
    float weight(int x, int y) const {
        return m_weight.empty() ? 1.f : m_weight[size_t(y) * size_t(m_width) + size_t(x)];
    }

    bool active(int x, int y) const { return m_active[size_t(y) * size_t(m_width) + size_t(x)] != 0; }
    const std::vector<uint8_t>& mask() const { return m_active; }
    // Pixels not stopped by the noise threshold (with allocation some of them may skip the next pass).
    size_t active_count() const { return m_live_count; }
    double active_fraction() const { return m_active.empty() ? 0.0 : double(m_live_count) / double(m_active.size()); }
    bool converged() const { return !m_active.empty() && m_live_count == 0; }
    // The largest filtered relative MSE among the pixels still active after the last update (0 before any).
    double worst_rel_mse() const { return m_worst; }

private:
    int m_width = 0, m_height = 0;
    std::vector<uint8_t> m_active;   // takes a sample in the next pass
    std::vector<uint8_t> m_stopped;  // stopped by the noise threshold, for good
    size_t m_live_count = 0;         // pixels not stopped
    double m_worst = 0.0;
    std::vector<float> m_weight;        // allocation weights in [kAllocationFloor, 1]; empty: all 1
    std::vector<uint32_t> m_next;       // allocation: each pixel's next sample index
    std::vector<uint64_t> m_rays;       // allocation: rays traced by each pixel's samples
    std::vector<float> m_cost;          // scratch: window-averaged rays per sample
    std::vector<float> m_error, m_row;  // scratch: per-pixel values, row-filtered values
    std::vector<float> m_filtered;      // scratch: window-averaged relative variance per sample
    std::vector<float> m_sorted;        // scratch: the quantile of r
};

}  // namespace pv
