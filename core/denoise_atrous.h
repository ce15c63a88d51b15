// core/denoise_atrous.h: the interactive denoiser: an edge-avoiding a-trous wavelet filter (Dammertz et al. 2010)
// with SVGF's weights (Schied et al. 2017): five passes of a 5x5 B3-spline kernel at strides 1, 2, 4, 8, 16,
// stopped at normal, depth and albedo edges and, on the colour, at differences larger than a few standard
// deviations of the per-pixel noise (the variance of the mean, filtered along). The colour is divided by the
// albedo before filtering and multiplied back after, so textures and colour edges stay sharp. Linear RGB in and
// out; no state between calls (the accumulation is never touched).
#pragma once

#include "core/aov.h"
#include "core/film.h"

namespace pv {

// Denoises `mean` given its per-pixel variance of the mean (per channel) and the first-hit features (same size).
// One core; about 5 x 25 taps per pixel.
Image denoise_atrous(const Image& mean, const Image& variance_of_mean, const FeatureImage& features);

}  // namespace pv
