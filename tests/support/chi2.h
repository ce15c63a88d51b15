// tests/support/chi2.h: chi-square goodness-of-fit test of a direction sampler against its pdf, after Mitsuba 3's
// ChiSquareTest (src/python/python/chi2.py; Mitsuba 3's chi-square goodness-of-fit test), written from the description:
//  1. n samples are mapped to (phi, cos theta) on [-pi, pi] x [-1, 1], an equal-area parameterisation of the sphere
//     (d omega = d phi d cos theta), and histogrammed on a res_phi x res_cos grid (res_cos odd: no cell boundary
//     at the horizon);
//  2. expected counts integrate pdf() over each cell (adaptive Simpson: cells split in four until converged) times n;
//  3. cells are sorted by expected count, those below 5 pooled, and Pearson's statistic computed;
//  4. p = Q(dof/2, chi2/2) is compared with the Sidak-corrected level 1 - (1 - 0.01)^(1/test_count).
// Sanity checks, as in Mitsuba: every sample is a unit vector, no sample lands where the expected count is 0,
// the pdf integral and the sampled fraction are <= 1 (+ tolerance).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/base/math.h"
#include "core/sampling/rng.h"

namespace pv::test {

struct Chi2Options {
    int res_cos = 51;
    int res_phi = 102;
    int ires = 2;  // Simpson sub-intervals per (sub-)cell side (even); cells are refined adaptively
    size_t sample_count = 1000000;
    double test_count = 1;  // tests in the family, for the Sidak correction
    double alpha = 0.01;
    uint64_t seed = 1;
};

struct Chi2Result {
    bool passed = false;
    double p = 0.0, level = 0.0, chi2 = 0.0;
    int dof = 0;
    double pdf_integral = 0.0;      // integral of pdf over the sphere
    double sampled_fraction = 0.0;  // samples that produced a direction / sample_count
    std::string message;            // why it failed, or a summary
};

// sample(rng) returns a direction (or nothing when the sampler rejects); pdf(w) its solid-angle density.
using DirectionSampler = std::function<std::optional<vec3>(Pcg32& rng)>;
using DirectionPdf = std::function<double(vec3 w)>;

Chi2Result chi2_test(const DirectionSampler& sample, const DirectionPdf& pdf, const Chi2Options& options);

}  // namespace pv::test
