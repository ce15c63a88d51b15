// core/denoise/denoise_nfor.h: the final-quality denoiser, after Bitterli et al. 2016, "Nonlinearly Weighted
// First-order Regression for Denoising Monte Carlo Renderings" (NFOR). Each pixel's colour is a weighted first-order
// regression on the first-hit features (albedo, shading normal, depth) and the screen offset over a window. Linear RGB
// in, linear RGB out.
#pragma once

#include <atomic>

#include "core/denoise/aov.h"
#include "core/image/film.h"

// Cross filtering: the two half buffers (even/odd samples, independent: core/sampling/sampler.h) are filtered
// crosswise: half A is regressed with weights computed from half B's colours and vice versa, so a weight never sees
// the noise it averages; the centre pixel's own guide colour is taken from its eight neighbours, so the filtered pixel
// does not see the other half's noise there either. Candidates: three colour bandwidths, and the a-trous filter
// (core/denoise/denoise_atrous.h) with four edge stops (from the viewer's to the normals' only), each half guided by
// itself. Per pixel the candidate whose filtered halves are closest to the OTHER half (an unbiased MSE estimate once
// that half's variance is subtracted; docs/denoise.md), after smoothing the error maps over 17 x 17, is kept: the mean
// of its filtered halves (regression) or its filter of the full mean (a-trous).

namespace pv {

struct NforStats {
    double seconds = 0.0;
    int bandwidths = 0;       // candidates: the regression's colour bandwidths, then the a-trous edge stops
    std::vector<int> chosen;  // pixels per candidate
};

// Denoises the film's mean with `features` (same size; render_features). Pixels with fewer than 2 samples in a
// half are passed through. Parallel over rows (TBB). When *cancel turns true the remaining rows are skipped and an
// empty image (0x0) is returned.
Image denoise_nfor(const Film& film, const FeatureImage& features, NforStats* stats = nullptr,
                   const std::atomic<bool>* cancel = nullptr);

}  // namespace pv
