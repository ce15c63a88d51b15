// core/denoise/denoise_atrous.h: the interactive denoiser: an edge-avoiding a-trous wavelet filter (Dammertz et al.
// 2010) with SVGF's weights (Schied et al. 2017). Linear RGB in and out; no state between calls but reused memory (the
// accumulation is never touched). The filter and how it is made fast: below the includes.
#pragma once

#include <vector>

#include "core/denoise/aov.h"
#include "core/image/film.h"

// The filter: four passes of a 3x3 B-spline kernel (1/4, 1/2, 1/4) at strides 1, 2, 4, 8 (a 31x31 footprint),
// stopped at normal and depth edges and, on the colour, at differences larger than a few standard deviations of the
// per-pixel noise (the variance of the mean, filtered along). The colour is divided by the albedo before filtering and
// multiplied back after, so textures and colour edges stay sharp.
//
// Built for speed on one core: the features are laid out once per camera as planes (one float array per
// channel; AtrousDenoiser::set_features), with each pixel's normalisers (1 / depth scale, 1 / colour sigma)
// precomputed; away from the border all eight taps of a pixel run in one branch-free loop body that the compiler
// vectorises (near the border, tap by tap over row segments, the same arithmetic); the
// edge-stopping exp(-e) is replaced by max(0, 1 - e/16)^16 (four squarings; within 0.018 of exp(-e) everywhere, 0
// beyond e = 16). About 9 x 4 taps per pixel. (Against five passes of 5x5 taps with exp, albedo stopping and scalar
// loops: 12-14x faster, for a 16-spp error at 512x512 Cornell of 5.9e-4 instead of 3.6e-4, against 3.7e-3 for the
// noisy 32-spp image: docs/denoise.md.)

namespace pv {

// The filter with its working memory kept between calls (no allocation per frame once the size is stable).
// Not thread-safe: one per thread.
class AtrousDenoiser {
public:
    // sigma_colour: the colour (luminance) difference, in standard deviations of the noise, at which a
    // neighbour's weight falls to about 1/e; sigma_depth: the same for the depth difference relative to the pixel's
    // depth, per unit of the pass's stride. The viewer's filter keeps the defaults; the final denoiser also tries
    // wider ones (core/denoise/denoise_nfor.h).
    explicit AtrousDenoiser(float sigma_colour = 4.f, float sigma_depth = 0.02f)
        : m_sigma_colour(sigma_colour), m_sigma_depth(sigma_depth) {}

    // Denoises `mean` given its per-pixel variance of the mean (per channel) and the first-hit features (all the
    // same size) into `out` (resized). One core.
    void denoise(const Image& mean, const Image& variance_of_mean, const FeatureImage& features, Image& out);

    // The same in two steps, for a series of frames of one camera: set_features lays the features out once (they
    // change only with the camera), then denoise each frame. Throws pv::Error when the sizes differ.
    void set_features(const FeatureImage& features);
    void denoise(const Image& mean, const Image& variance_of_mean, Image& out);

private:
    float* plane(int k);

    float m_sigma_colour, m_sigma_depth;
    int m_w = 0, m_h = 0;
    // Planes of w*h floats: demodulation albedo (3), colour (3), variance, unit normal (3), valid (normal not 0),
    // depth, 1 / depth scale, luminance, 1 / colour sigma, and the next pass's colour (3) and variance.
    std::vector<float> m_planes;
    std::vector<float> m_rows;  // accumulators of one row (5 x w) and the variance box filter's row sums
};

// One call of a fresh AtrousDenoiser.
Image denoise_atrous(const Image& mean, const Image& variance_of_mean, const FeatureImage& features);

// The variance of each pixel's mean that the filter's colour stopping is scaled by: the film's own (sample variance
// over n) where a pixel has two samples or more; where it has fewer (every pixel of an accumulation's first pass),
// the spread of its 3x3 neighbourhood's means (SVGF's spatial estimate while a pixel's history is short), since a
// variance of 0 would let the filter accept no neighbour and show the 1-spp image as it is.
Image atrous_variance(const Film& film);

}  // namespace pv
