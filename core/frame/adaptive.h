// core/frame/adaptive.h: where and how long to sample: a noise threshold that stops pixels whose estimated error is
// low, and an unbiased allocation of samples in proportion to each pixel's relative error per sample (both below).
#pragma once

#include <cstdint>
#include <vector>

#include "core/image/film.h"

// Noise threshold (AdaptiveSettings::noise_threshold): after a pass, each pixel's relative error is estimated from
// the film's two half buffers (pixel_rel_mse: relative to mean^2 + 0.01, as the metrics); its per-sample relative
// variance (that times the pixel's count) is averaged over a (2r+1)^2 neighbourhood, because one pixel's estimate
// has only about 3 degrees of freedom, and divided by the pixel's count again; a pixel whose filtered relative RMS
// error is below the noise threshold takes no more samples. Pixels are judged only at the checkpoint counts 2^k and
// 3 x 2^(k-1): a geometric schedule, so a pixel is looked at O(log n) times (each look is a chance to stop on an
// estimate that happens to be low: stopping on the samples themselves biases the image, docs/convergence.md).
//
// Allocation (AdaptiveSettings::allocate, the command line's default) is unbiased at any sample count:
// the allocation never depends on the samples it steers. Passes 1..kPilotPasses and every kPilotEvery-th pass
// after are pilot passes: every pixel takes a sample, rendered with its own seed
// (pilot_seed: a scramble independent of the main samples'), into a separate pilot film. The weights come from the
// pilot film alone: the mean relMSE at a fixed budget is lowest with each pixel's count n_i proportional to r_i /
// sqrt(c_i) (r_i its relative standard deviation per sample, c_i its cost: minimise sum r_i^2 / n_i subject to sum c_i
// n_i = N); r_i^2 is the pilot's half-buffer estimate times its count, c_i one plus the pilot samples' rays per sample,
// both averaged over the (2r+1)^2 window; w_i = s_i / s_ref with s_i = r_i / sqrt(c_i) and s_ref the
// kAllocationQuantile quantile of s over the image (a robust maximum), clamped to [kAllocationFloor, 1], recomputed
// after every pilot pass. In main pass q a pixel takes a main sample while its main count is below q w_i. Given the
// pilot, a pixel's main count is fixed and its main samples are independent of the pilot, so their mean is unbiased;
// the pilot's mean is unbiased too. The image is a_i x pilot mean + (1 - a_i) x main mean with a_i = (pilot passes) /
// (all passes): a fixed weight, independent of every sample value (combine()), so the image's expectation is that of
// --adaptive off. A pixel's main samples take the indices 0, 1, 2... of its own count, so they are the ones a uniform
// render of that many passes gives it (Sobol's stratification holds per pixel); pilot samples likewise under the pilot
// seed. Everything depends only on the films and the counts, so images stay identical for any thread count.

namespace pv {

constexpr double kAllocationQuantile = 0.97;  // r_ref: this quantile of the pixels' relative error per sample
constexpr float kAllocationFloor = 0.25f;     // the least weight: a quarter of the noisiest pixels' rate
constexpr uint32_t kPilotPasses = 8;          // allocation: passes 1..8 are pilot passes...
constexpr uint32_t kPilotEvery = 8;           // ...and every 8th pass after them

// Allocation: whether pass number `pass` (1-based) is a pilot pass.
inline bool is_pilot_pass(uint32_t pass) { return pass <= kPilotPasses || pass % kPilotEvery == 0; }
// The seed of the pilot samples: a different Sobol scramble / random stream from the main samples'.
inline uint32_t pilot_seed(uint32_t seed) { return seed ^ 0x9e3779b9u; }

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
    // After pass number `spp` (1-based count of passes so far) has landed in `film`: with a noise threshold, on a
    // checkpoint count >= min_spp, pixels whose filtered error is below the threshold stop. A stopped pixel never
    // restarts.
    void update(const Film& film, uint32_t spp, const AdaptiveSettings& settings);
    // Allocation: the weights from the pilot film (once it has kPilotPasses passes), after a pilot pass.
    void update_weights(const Film& pilot, const AdaptiveSettings& settings);
    // Allocation: before a pass, marks active the pixels not stopped and, for main pass number `main_pass`
    // (1-based count of main passes), whose main count is below main_pass x weight.
    void prepare_pass(bool pilot, uint32_t main_pass);
    // Allocation: the image's film from the pilot and main films (see above), written over `out`.
    void combine(const Film& pilot, const Film& main, Film& out) const;

private:
    void combine_groups(const Film& pilot, const Film& main, Film& out) const;

public:
    // With allocation, each pixel's next main (pilot) sample index: its count of main (pilot) samples taken; the
    // pass's worker that owns the pixel advances it.
    uint32_t& next_index(int x, int y) { return m_next[size_t(y) * size_t(m_width) + size_t(x)]; }
    uint32_t& pilot_index(int x, int y) { return m_pilot_next[size_t(y) * size_t(m_width) + size_t(x)]; }
    // With allocation, the rays a pilot sample of pixel (x, y) traced: the cost side of the weights.
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
    void filter_error(const Film& film, int radius);  // m_error, m_filtered from the film's half buffers

    int m_width = 0, m_height = 0;
    std::vector<uint8_t> m_active;   // takes a sample in the next pass
    std::vector<uint8_t> m_stopped;  // stopped by the noise threshold, for good
    size_t m_live_count = 0;         // pixels not stopped
    double m_worst = 0.0;
    std::vector<float> m_weight;         // allocation weights in [kAllocationFloor, 1]; empty: all 1
    std::vector<uint32_t> m_next;        // allocation: each pixel's next main sample index
    std::vector<uint32_t> m_pilot_next;  // allocation: each pixel's next pilot sample index (its pilot passes)
    std::vector<uint32_t> m_main_live;   // allocation: main passes while the pixel was not stopped
    std::vector<uint64_t> m_rays;        // allocation: rays traced by each pixel's pilot samples
    std::vector<float> m_cost;           // scratch: window-averaged rays per sample
    std::vector<float> m_error, m_row;   // scratch: per-pixel values, row-filtered values
    std::vector<float> m_filtered;       // scratch: window-averaged relative variance per sample
    std::vector<float> m_sorted;         // scratch: the quantile of r
};

}  // namespace pv
