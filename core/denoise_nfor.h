// core/denoise_nfor.h: the final-quality denoiser, after Bitterli et al. 2016, "Nonlinearly Weighted First-order
// Regression for Denoising Monte Carlo Renderings" (NFOR). Each pixel's colour is a weighted first-order
// regression on the first-hit features (albedo, shading normal, depth) and the screen offset over a window. The
// two half buffers (even/odd samples, independent: core/sampler.h) are filtered crosswise: half A is regressed with
// weights computed from half B's colours and vice versa, so a weight never sees the noise it averages. Candidates:
// three colour bandwidths, and the a-trous filter (core/denoise_atrous.h) of each half; per pixel the one whose
// filtered half is closest to the OTHER half (an MSE estimate once that half's variance is subtracted), after
// smoothing the error map, is kept. Output: the mean of the two filtered halves. Linear RGB in, linear RGB out.
// Known limit (docs/denoise.md): for the regression candidates the estimate runs low, because half A's filter
// weights come from half B, the half it is compared with; the narrowest bandwidth is then chosen too often (88% of
// the pixels of the sunlit room at 16 spp) and the a-trous candidate too rarely.
#pragma once

#include "core/aov.h"
#include "core/film.h"

namespace pv {

struct NforStats {
    double seconds = 0.0;
    int bandwidths = 0;       // candidates: the colour bandwidths, then the a-trous filter
    std::vector<int> chosen;  // pixels per candidate
};

// Denoises the film's mean with `features` (same size; render_features). Pixels with fewer than 2 samples in a
// half are passed through. Parallel over rows (TBB).
Image denoise_nfor(const Film& film, const FeatureImage& features, NforStats* stats = nullptr);

}  // namespace pv
