// tests/scene/test_bsdf_fast.cpp: the fast paths of core/sampling/warp.h and core/scene/bsdf.h against straightforward
// references in double (the formulas they replaced): the polynomial sin/cos (stated error bounds), the concentric disk
// map, the inline Lambertian dispatch (two-sided rules, edge cases) and the one-division GGX eval/pdf (rel 1e-5).
// Test kinds: unit
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/sampling/rng.h"
#include "core/sampling/warp.h"
#include "core/scene/bsdf.h"

namespace pv {
namespace {

// ---------------------------------------------------------------- sin/cos

// Max abs error over [-pi/4, pi/4] against double sin/cos at the same float argument: documented < 6e-8.
TEST(FastSinCos, ReducedRangeWithinBound) {
    const int n = 1 << 20;
    double max_err = 0.0;
    for (int i = 0; i <= n; ++i) {
        const float x = float(-M_PI / 4 + (M_PI / 2) * i / n);
        const vec2 cs = cos_sin_reduced(x);
        max_err = std::max(max_err, std::fabs(cs.x - std::cos(double(x))));
        max_err = std::max(max_err, std::fabs(cs.y - std::sin(double(x))));
    }
    EXPECT_LT(max_err, 1.2e-7);  // 2^-23: about one ulp of 1
}

// (cos 2 pi u, sin 2 pi u) over [0, 1), quadrant boundaries included; the bound adds the rounding of the
// reduced angle (q - k) * pi/2 to the polynomial's error.
TEST(FastSinCos, TurnsWithinBoundOverFullCircle) {
    const int n = 1 << 20;
    double max_err = 0.0;
    auto check = [&](float u) {
        const vec2 cs = cos_sin_turns(u);
        const double phi = 2.0 * M_PI * double(u);
        max_err = std::max(max_err, std::fabs(cs.x - std::cos(phi)));
        max_err = std::max(max_err, std::fabs(cs.y - std::sin(phi)));
        EXPECT_LE(double(cs.x) * cs.x + double(cs.y) * cs.y, 1.0 + 3e-7) << u;
    };
    for (int i = 0; i < n; ++i) check(float(i) / n);
    for (float b : {0.125f, 0.25f, 0.375f, 0.5f, 0.625f, 0.75f, 0.875f}) {
        check(std::nextafter(b, 0.f));
        check(b);
        check(std::nextafter(b, 1.f));
    }
    check(std::nextafter(1.f, 0.f));
    EXPECT_LT(max_err, 2.5e-7);
    EXPECT_EQ(cos_sin_turns(0.f), vec2(1.f, 0.f));
}

// ---------------------------------------------------------------- concentric disk

// The pbrt-v4 / Shirley-Chiu map with libm sin/cos, in double.
glm::dvec2 concentric_reference(vec2 u) {
    const double ox = 2.0 * u.x - 1.0, oy = 2.0 * u.y - 1.0;
    if (ox == 0 && oy == 0) return glm::dvec2(0.0);
    double r, theta;
    if (std::fabs(ox) > std::fabs(oy)) {
        r = ox;
        theta = (M_PI / 4) * (oy / ox);
    } else {
        r = oy;
        theta = M_PI / 2 - (M_PI / 4) * (ox / oy);
    }
    return r * glm::dvec2(std::cos(theta), std::sin(theta));
}

TEST(FastWarp, ConcentricMatchesReference) {
    const int n = 1024;
    double max_err = 0.0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            // The grid includes the centre, the square's edges and both diagonals (the wedge boundaries).
            const vec2 u(float(i) / n, float(j) / n);
            const glm::dvec2 d = glm::dvec2(square_to_disk_concentric(u)) - concentric_reference(u);
            max_err = std::max(max_err, std::max(std::fabs(d.x), std::fabs(d.y)));
        }
    EXPECT_LT(max_err, 3e-7);
    EXPECT_EQ(square_to_disk_concentric(vec2(0.5f)), vec2(0.f));
}

// ---------------------------------------------------------------- Lambertian (inline dispatch)

TEST(FastBsdf, LambertianIsTwoSidedWithStrictSides) {
    const Bsdf b = Lambertian{vec3(0.6f, 0.3f, 0.1f)};
    const vec3 f = vec3(0.6f, 0.3f, 0.1f) * kInvPi;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const vec3 up(0.f, 0.6f, 0.8f), down(0.f, 0.6f, -0.8f);
    EXPECT_EQ(eval(b, up, up), f);
    EXPECT_EQ(eval(b, down, down), f);
    EXPECT_EQ(eval(b, up, down), vec3(0.f));
    EXPECT_EQ(eval(b, down, up), vec3(0.f));
    EXPECT_EQ(eval(b, vec3(1.f, 0.f, 0.f), up), vec3(0.f));
    EXPECT_EQ(eval(b, vec3(1.f, 0.f, -0.f), down), vec3(0.f));
    EXPECT_EQ(eval(b, vec3(0.f, 0.f, nan), up), vec3(0.f));
    EXPECT_FLOAT_EQ(pdf(b, up, up), 0.8f * kInvPi);
    EXPECT_FLOAT_EQ(pdf(b, down, down), 0.8f * kInvPi);
    EXPECT_EQ(pdf(b, up, down), 0.f);
    EXPECT_EQ(pdf(b, down, up), 0.f);
    EXPECT_EQ(pdf(b, vec3(1.f, 0.f, 0.f), up), 0.f);
    EXPECT_FALSE(sample(b, vec3(1.f, 0.f, 0.f), 0.5f, vec2(0.3f, 0.7f)));
    EXPECT_FALSE(is_delta(b));
    EXPECT_TRUE(is_delta(Bsdf{Mirror{}}));
    EXPECT_TRUE(is_delta(Bsdf{Dielectric{}}));
    EXPECT_FALSE(is_delta(Bsdf{Glossy{}}));

    Pcg32 g(3, 4);
    for (int i = 0; i < 10000; ++i) {
        const vec3 wo = g.next_float() < 0.5f ? up : down;
        const auto s = sample(b, wo, g.next_float(), vec2(g.next_float(), g.next_float()));
        ASSERT_TRUE(s);
        ASSERT_EQ(s->wi.z > 0.f, wo.z > 0.f);
        ASSERT_EQ(s->f, f);
        ASSERT_EQ(s->pdf, pdf(b, wo, s->wi));
        ASSERT_FALSE(s->is_delta);
        ASSERT_EQ(s->eta, 1.f);
    }
}

// The integrator traces a textured surface's shadow ray before looking its colour up, and skips directions where
// reflects(wo, wi) is false: every lobe light sampling evaluates (the non-delta ones) must then be black there,
// whatever its base colour. Random colours and directions, with both hemispheres and the grazing plane.
TEST(FastBsdf, NonDeltaLobesAreBlackWhereReflectsIsFalse) {
    Pcg32 g(21, 22);
    const std::vector<Bsdf> kinds = {Lambertian{},
                                     Glossy{vec3(0.5f), vec3(0.04f), 0.2f},
                                     Glossy{vec3(0.2f), vec3(0.5f), 0.9f},
                                     Glossy{vec3(0.f), vec3(1.f), 0.01f},
                                     Mirror{},
                                     Dielectric{}};
    auto direction = [&] {
        vec3 w = square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
        if (g.next_float() < 0.1f) w.z = g.next_float() < 0.5f ? 0.f : -0.f;  // in the surface's plane
        return w;
    };
    int black = 0;
    for (const Bsdf& kind : kinds) {
        if (is_delta(kind)) continue;  // light sampling never evaluates a delta lobe
        for (int i = 0; i < 20000; ++i) {
            Bsdf b = kind;
            set_base_color(b, vec3(g.next_float(), g.next_float(), g.next_float()));
            const vec3 wo = direction(), wi = direction();
            if (reflects(wo, wi)) continue;
            ASSERT_EQ(eval(b, wo, wi), vec3(0.f)) << bsdf_type_name(b) << " wo.z " << wo.z << " wi.z " << wi.z;
            ++black;
        }
    }
    EXPECT_GT(black, 30000);  // about half of the 4 x 20000 pairs
}

// ---------------------------------------------------------------- GGX glossy (one-division form)

// The textbook form in double: D(h) G1(wo) G1(wi) / (4 cos_o cos_i) and the VNDF pdf G1(wo) D(h) / (4 cos_o).
struct GlossyRef {
    dvec3 f;
    double pdf;
};
GlossyRef glossy_reference(const Glossy& b, vec3 wo_f, vec3 wi_f) {
    dvec3 wo(wo_f), wi(wi_f);
    if (wo.z < 0) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    if (wo.z <= 0 || wi.z <= 0) return {dvec3(0.0), 0.0};
    const double a2 = double(b.alpha) * b.alpha;
    const dvec3 h = glm::normalize(wo + wi);
    const double d = h.z * h.z * (a2 - 1) + 1;
    const double D = a2 / (M_PI * d * d);
    auto g1 = [&](dvec3 w) { return 2 / (1 + std::sqrt(1 + a2 * (1 - w.z * w.z) / (w.z * w.z))); };
    const double spec = 0.25 * D * g1(wo) / wo.z * g1(wi) / wi.z;
    const double s = luminance(b.specular), dl = luminance(b.diffuse);
    const double ps = s + dl > 0 ? s / (s + dl) : 1;
    const double pdf_spec = g1(wo) * D / (4 * wo.z);
    return {dvec3(b.diffuse) / M_PI + dvec3(b.specular) * spec, ps * pdf_spec + (1 - ps) * wi.z / M_PI};
}

TEST(FastBsdf, GlossyEvalAndPdfMatchTextbookForm) {
    Pcg32 g(11, 12);
    for (float alpha : {kMinAlpha, 0.05f, 0.3f, 1.f}) {
        const Glossy gl{vec3(0.2f, 0.1f, 0.05f), vec3(0.5f), alpha};
        const Bsdf b = gl;
        for (int i = 0; i < 50000; ++i) {
            vec3 wo = square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
            vec3 wi = square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
            if (i % 4 == 0) wo = glm::normalize(vec3(wo.x, wo.y, 1e-3f * wo.z));                     // near grazing
            if (i % 8 == 1) wi = glm::normalize(wo * vec3(1.f, 1.f, 1.f + 1e-3f * g.next_float()));  // h near z
            const GlossyRef r = glossy_reference(gl, wo, wi);
            const vec3 f = eval(b, wo, wi);
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(f[c], r.f[c], 1e-5 * r.f[c] + 1e-30) << alpha << " " << i;
            ASSERT_NEAR(pdf(b, wo, wi), r.pdf, 1e-5 * r.pdf + 1e-30) << alpha << " " << i;
        }
    }
}

// ---------------------------------------------------------------- dielectric refraction

TEST(FastBsdf, DielectricRefractionMatchesSnell) {
    const float eta = 1.5f;
    const Bsdf b = Dielectric{eta};
    for (float c : {0.9f, 0.5f, 0.1f, -0.8f, -0.95f}) {  // inside: above the critical cos 0.745
        const vec3 wo(std::sqrt(1.f - c * c), 0.f, c);
        const auto s = sample(b, wo, 0.999999f, vec2(0.5f));  // u_lobe above Fresnel: refraction
        ASSERT_TRUE(s) << c;
        const double e = c > 0 ? eta : 1.0 / eta;  // relative IOR seen from wo's side
        const double sin_t = std::sqrt(1.0 - double(c) * c) / e;
        EXPECT_NEAR(s->wi.x, -sin_t, 1e-6) << c;
        EXPECT_NEAR(s->wi.z, (c > 0 ? -1 : 1) * std::sqrt(1 - sin_t * sin_t), 1e-6) << c;
        const double t = 1.0 - fresnel_dielectric(c, eta);
        EXPECT_NEAR(s->f.x, t / (e * e) / std::fabs(double(s->wi.z)), 1e-5 * s->f.x) << c;
        EXPECT_FLOAT_EQ(s->eta, float(e)) << c;
    }
}

}  // namespace
}  // namespace pv
