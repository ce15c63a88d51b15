// tests/scene/test_sheen.cpp: the Charlie sheen lobe (core/scene/sheen.h, issue 37 item 2):
//  * D is a normalised microfacet distribution: the integral of D(h) cos_h over the hemisphere is 1;
//  * the lobe is reciprocal;
//  * the compiled-in albedo table (scripts/make_sheen_table.py) agrees with this test's own numerical integration of
//    the lobe, at nodes and between them (bilinear), and stays in [0, 1].
// Test kinds: unit
#include <gtest/gtest.h>

#include <cmath>

#include "core/scene/sheen.h"

namespace pv {
namespace {

vec3 dir(float cos_t, float phi) {
    const float s = std::sqrt(std::max(0.f, 1.f - cos_t * cos_t));
    return vec3(s * std::cos(phi), s * std::sin(phi), cos_t);
}

// Midpoint rule in (cos_i, phi), in double.
double albedo_by_quadrature(float mu, float alpha, int nu = 512, int nphi = 256) {
    const vec3 wo = dir(mu, 0.f);
    double sum = 0.0;
    for (int i = 0; i < nu; ++i) {
        const float ci = (float(i) + 0.5f) / float(nu);
        for (int k = 0; k < nphi; ++k) {
            const float phi = (float(k) + 0.5f) / float(nphi) * 2.f * kPi;
            sum += double(sheen_eval(wo, dir(ci, phi), alpha)) * ci;
        }
    }
    return sum * (1.0 / nu) * (2.0 * M_PI / nphi);
}

TEST(Sheen, DistributionIsNormalised) {
    for (float alpha : {0.05f, 0.2f, 0.5f, 1.f}) {
        const int n = 20000;
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
            const float c = (float(i) + 0.5f) / float(n);
            sum += double(sheen_d(c, alpha)) * c;
        }
        EXPECT_NEAR(sum * 2.0 * M_PI / n, 1.0, 2e-3) << "alpha " << alpha;
    }
}

TEST(Sheen, Reciprocal) {
    for (float alpha : {0.05f, 0.4f, 1.f})
        for (float a : {0.1f, 0.5f, 0.9f})
            for (float b : {0.2f, 0.7f, 1.f}) {
                const vec3 wo = dir(a, 0.3f), wi = dir(b, 2.1f);
                EXPECT_NEAR(sheen_eval(wo, wi, alpha), sheen_eval(wi, wo, alpha),
                            1e-5f * std::max(1.f, sheen_eval(wo, wi, alpha)));
            }
}

TEST(Sheen, AlbedoTableMatchesQuadrature) {
    // at table nodes (i/15, j/15) and halfway between (bilinear interpolation's error is part of the bound)
    for (float mu : {0.2f, 1.f / 3.f, 0.5f, 0.7f, 1.f})
        for (float alpha : {0.2f, 1.f / 3.f, 0.5f, 0.8f, 1.f}) {
            const double ref = albedo_by_quadrature(mu, alpha);
            const float tab = sheen_albedo(mu, alpha);
            EXPECT_NEAR(tab, ref, 0.01) << "mu " << mu << " alpha " << alpha;
            EXPECT_GE(tab, 0.f);
            EXPECT_LE(tab, 1.f);
        }
}

}  // namespace
}  // namespace pv
