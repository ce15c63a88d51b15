// tests/sampling/test_sampling.cpp: statistical tests of every sampling routine (chi-square goodness of fit,
// eval/pdf/sample consistency, albedo <= 1, reciprocity):
//  * chi-square goodness of fit (tests/support/chi2.h) of the hemisphere/sphere warps, the Lambertian, the GGX
//    glossy lobe at alpha 0.05/0.2/0.6/1 and several wo down to near grazing, diffuse + GGX, and triangle light
//    sampling (area sampling converted to solid angle);
//  * the dielectric's reflect/refract choice against Fresnel (binomial z-test) and Snell's law;
//  * sample() agrees with eval() and pdf() (rel 1e-5), reciprocity (rel 1e-4);
//  * directional albedo <= 1 at cos(wo) in {1, 0.5, 0.1, 1e-3}, by uniform-hemisphere and BSDF sampling, which
//    must agree; exactly 1 for albedo-1 Lambert, the mirror and lossless glass.
// Test kinds: statistical; analytic: BsdfAlbedo DielectricSampling; unit: BsdfConsistency LightSampling
#include <gtest/gtest.h>

#include <cstring>

#include "core/render/lights.h"
#include "core/sampling/warp.h"
#include "core/scene/bsdf.h"
#include "tests/support/chi2.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

using test::chi2_test;
using test::Chi2Options;

vec3 dir_from_cos(float cos_theta, float phi = 0.7f) {
    const float s = safe_sqrt(1.f - cos_theta * cos_theta);
    return vec3(s * std::cos(phi), s * std::sin(phi), cos_theta);
}

// ---------------------------------------------------------------- warps

TEST(Chi2Warp, CosineHemisphere) {
    Chi2Options o;
    o.test_count = 3;
    const auto r = chi2_test(
        [](Pcg32& g) -> std::optional<vec3> {
            return square_to_cosine_hemisphere(vec2(g.next_float(), g.next_float()));
        },
        [](vec3 w) { return double(cosine_hemisphere_pdf(w.z)); }, o);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3);
}

TEST(Chi2Warp, UniformSphereAndHemisphere) {
    Chi2Options o;
    o.test_count = 3;
    const auto a = chi2_test(
        [](Pcg32& g) -> std::optional<vec3> { return square_to_uniform_sphere(vec2(g.next_float(), g.next_float())); },
        [](vec3) { return double(uniform_sphere_pdf()); }, o);
    EXPECT_TRUE(a.passed) << a.message;
    const auto b = chi2_test(
        [](Pcg32& g) -> std::optional<vec3> {
            return square_to_uniform_hemisphere(vec2(g.next_float(), g.next_float()));
        },
        [](vec3 w) { return w.z > 0 ? double(uniform_hemisphere_pdf()) : 0.0; }, o);
    EXPECT_TRUE(b.passed) << b.message;
}

// ---------------------------------------------------------------- BSDF lobes

struct LobeCase {
    std::string name;
    Bsdf bsdf;
    float cos_wo;
    int ires;
};

void PrintTo(const LobeCase& c, std::ostream* os) { *os << c.name; }

std::vector<LobeCase> lobe_cases() {
    std::vector<LobeCase> out;
    auto label = [](float c) {
        std::string s = std::to_string(c);
        for (char& ch : s)
            if (ch == '.' || ch == '-') ch = '_';
        return s.substr(0, 6);
    };
    for (float c : {1.f, 0.5f, 0.05f, -0.6f}) out.push_back({"Lambert_cos" + label(c), Lambertian{vec3(0.7f)}, c, 2});
    for (float alpha : {0.05f, 0.2f, 0.6f, 1.f})
        for (float c : {1.f, 0.6f, 0.2f, 0.02f})
            out.push_back({"Ggx_a" + label(alpha) + "_cos" + label(c), Glossy{vec3(0.f), vec3(1.f), alpha}, c, 4});
    for (float c : {0.9f, 0.3f, -0.5f})
        out.push_back({"DiffuseGgx_cos" + label(c), Glossy{vec3(0.4f), vec3(0.3f), 0.3f}, c, 2});
    return out;
}

class Chi2Bsdf : public testing::TestWithParam<LobeCase> {};

TEST_P(Chi2Bsdf, SamplesFollowPdf) {
    const LobeCase c = GetParam();
    const vec3 wo = dir_from_cos(c.cos_wo);
    Chi2Options o;
    o.test_count = double(lobe_cases().size());
    o.ires = c.ires;
    o.seed = std::hash<std::string>()(c.name) | 1;
    const auto r = chi2_test(
        [&](Pcg32& g) -> std::optional<vec3> {
            const float ul = g.next_float();
            const vec2 u(g.next_float(), g.next_float());
            const auto s = sample(c.bsdf, wo, ul, u);
            if (!s || !(s->pdf > 0.f) || is_black(s->f)) return std::nullopt;
            return s->wi;
        },
        [&](vec3 wi) { return double(pdf(c.bsdf, wo, wi)); }, o);
    EXPECT_TRUE(r.passed) << r.message;
    // A lobe loses only the samples its pdf does not cover (GGX samples below the horizon).
    EXPECT_NEAR(r.sampled_fraction, r.pdf_integral, 5e-3) << r.message;
}

INSTANTIATE_TEST_SUITE_P(Lobes, Chi2Bsdf, testing::ValuesIn(lobe_cases()),
                         [](const testing::TestParamInfo<LobeCase>& i) { return i.param.name; });

// ---------------------------------------------------------------- triangle lights

// Two-sided and one-sided emitters of different sizes, powers and orientations; a sample's direction density is
// the sum over every emissive triangle the ray from ref crosses of LightSet::pdf (Moller-Trumbore in double).
struct LightScene {
    Scene scene;
    std::unique_ptr<LightSet> lights;
    LightScene() {
        Material a, b, c, d;
        a.emission = vec3(4.f, 2.f, 1.f);
        b.emission = vec3(1.f);
        b.two_sided_emission = true;
        c.emission = vec3(20.f);
        const uint32_t ma = test::add_material(scene, a), mb = test::add_material(scene, b),
                       mc = test::add_material(scene, c), md = test::add_material(scene, d);
        test::add_quad(scene, vec3(-1, 2, -1), vec3(-1, 2, 1), vec3(1, 2, 1), vec3(1, 2, -1), ma);  // facing down
        scene.add_triangle(vec3(2, -1, 0), vec3(2, 1, 0.5f), vec3(2, 0, -1.5f), mb);                // side, two-sided
        scene.add_triangle(vec3(-0.1f, -2, 0.1f), vec3(0.1f, -2, 0.1f), vec3(0, -2, -0.1f), mc);    // small, below
        scene.add_triangle(vec3(0, 0, -3), vec3(1, 0, -3), vec3(0, 1, -3), md);                     // not a light
        lights = std::make_unique<LightSet>(scene, scene.materials);
    }
    double direction_pdf(vec3 ref, vec3 w) const {
        double total = 0.0;
        for (uint32_t i = 0; i < scene.triangles.size(); ++i) {
            if (lights->pmf(i) == 0.f) continue;
            const uvec3 t = scene.triangles[i];
            const dvec3 p0 = scene.positions[t.x], p1 = scene.positions[t.y], p2 = scene.positions[t.z];
            const dvec3 o = ref, d = w, e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
            const double det = glm::dot(e1, pv);
            if (det == 0.0) continue;
            const dvec3 tv = o - p0;
            const double u = glm::dot(tv, pv) / det;
            const dvec3 qv = glm::cross(tv, e1);
            const double v = glm::dot(d, qv) / det, tt = glm::dot(e2, qv) / det;
            if (u < 0 || v < 0 || u + v > 1 || tt <= 0) continue;
            const vec3 p = vec3(o + tt * d);
            const vec3 n = glm::normalize(glm::cross(vec3(e1), vec3(e2)));
            total += lights->pdf(i, ref, vec3(0.f), p, n);
        }
        return total;
    }
};

TEST(Chi2Light, TriangleLightsBySolidAngle) {
    const LightScene ls;
    ASSERT_EQ(ls.lights->size(), 4u);  // the quad's two triangles, the side and the small one
    const vec3 refs[] = {vec3(0.f), vec3(0.5f, 1.5f, 0.3f)};
    for (const vec3& ref : refs) {
        Chi2Options o;
        o.test_count = 2;
        const auto r = chi2_test(
            [&](Pcg32& g) -> std::optional<vec3> {
                const float us = g.next_float();
                const vec2 u(g.next_float(), g.next_float());
                LightSample s;
                if (!ls.lights->sample(ref, vec3(0.f), us, u, s)) return std::nullopt;
                return s.wi;
            },
            [&](vec3 w) { return ls.direction_pdf(ref, w); }, o);
        EXPECT_TRUE(r.passed) << "ref (" << ref.x << ", " << ref.y << ", " << ref.z << "): " << r.message;
        EXPECT_NEAR(r.pdf_integral, 1.0, 5e-3) << r.message;
    }
}

// Each sample's pdf equals pdf() for the same point, and the triangle pmf is power-proportional.
TEST(LightSampling, SamplePdfMatchesPdfAndPowerIsProportional) {
    const LightScene ls;
    Pcg32 g(3, 4);
    const vec3 ref(0.2f, 0.1f, -0.3f);
    for (int i = 0; i < 10000; ++i) {
        LightSample s;
        ASSERT_TRUE(ls.lights->sample(ref, vec3(0.f), g.next_float(), vec2(g.next_float(), g.next_float()), s));
        // Identify the triangle by the direction pdf (at most one triangle per direction here).
        const double p = ls.direction_pdf(ref, s.wi);
        EXPECT_NEAR(s.pdf, p, 1e-3 * p);
        EXPECT_NEAR(glm::length(s.p - ref), s.dist, 1e-4f * s.dist);
    }
    // pmf = luminance(Le) * area (* 2 if two-sided) / total.
    const double quad = 4.0 * double(luminance(vec3(4, 2, 1)));
    const double side = 2.0 * 0.5 * glm::length(glm::cross(vec3(0, 2, 0.5f), vec3(0, 1, -1.5f)));
    const double small = 20.0 * 0.5 * 0.2 * 0.2;
    const double total = quad + side + small;
    EXPECT_NEAR(ls.lights->pmf(0) + ls.lights->pmf(1), quad / total, 1e-6);
    EXPECT_NEAR(ls.lights->pmf(2), side / total, 1e-6);
    EXPECT_NEAR(ls.lights->pmf(3), small / total, 1e-6);
    EXPECT_EQ(ls.lights->pmf(4), 0.f);
    EXPECT_NEAR(ls.lights->total_power(), M_PI * total, 1e-4 * M_PI * total);
}

// skip_unlit (the path tracer's call) drops exactly the samples whose emission toward ref is black: a one-sided
// emitter seen from behind or edge-on. Every other sample is the full sampler's, bit for bit, so the estimator is
// unchanged. Points all around the lights, the solid-angle rule's region included.
TEST(LightSampling, SkipUnlitDropsExactlyTheBlackSamples) {
    const LightScene ls;
    Pcg32 g(7, 8);
    int skipped = 0, kept = 0;
    for (int i = 0; i < 20000; ++i) {
        const vec3 ref(6.f * g.next_float() - 3.f, 5.f * g.next_float() - 2.5f, 4.f * g.next_float() - 2.f);
        const float u_select = g.next_float();
        const vec2 u(g.next_float(), g.next_float());
        LightSample all, lit;
        const bool a = ls.lights->sample(ref, vec3(0.f), u_select, u, all);
        const bool b = ls.lights->sample(ref, vec3(0.f), u_select, u, lit, true);
        if (!b) {
            EXPECT_TRUE(!a || is_black(all.le))
                << "a lit sample was dropped at ref " << ref.x << " " << ref.y << " " << ref.z;
            skipped += a;
            continue;
        }
        ++kept;
        ASSERT_TRUE(a);
        EXPECT_EQ(std::memcmp(&all.p, &lit.p, sizeof(vec3)), 0);
        EXPECT_EQ(std::memcmp(&all.le, &lit.le, sizeof(vec3)), 0);
        EXPECT_EQ(all.pdf, lit.pdf);
        EXPECT_EQ(all.dist, lit.dist);
    }
    EXPECT_GT(skipped, 1000) << "points behind the one-sided lights";
    EXPECT_GT(kept, 5000);
}

// ---------------------------------------------------------------- dielectric

TEST(DielectricSampling, ReflectFrequencyMatchesFresnelAndSnell) {
    struct Case {
        float eta, cos_wo;
    };
    // Outside (+) and inside (-), including near grazing and near the critical angle (cos 0.745 for 1.5).
    const Case cases[] = {{1.5f, 1.f},   {1.5f, 0.5f},   {1.5f, 0.1f},  {1.5f, 1e-3f}, {1.5f, -0.95f},
                          {1.5f, -0.8f}, {1.5f, -0.75f}, {1.5f, -0.5f}, {1.33f, 0.3f}, {2.4f, -0.9f}};
    const double k = test::sidak_k(std::size(cases));
    const int n = 200000;
    for (size_t ci = 0; ci < std::size(cases); ++ci) {
        const Case& c = cases[ci];
        const Dielectric d{c.eta};
        const vec3 wo = dir_from_cos(c.cos_wo);
        const double r = fresnel_dielectric(c.cos_wo, c.eta);
        Pcg32 g(ci + 7, 11);
        int reflected = 0, produced = 0;
        for (int i = 0; i < n; ++i) {
            const auto s = sample(Bsdf(d), wo, g.next_float(), vec2(g.next_float(), g.next_float()));
            if (!s) continue;
            ++produced;
            ASSERT_TRUE(s->is_delta);
            ASSERT_TRUE(is_finite(s->f) && s->pdf > 0.f);
            const bool refl = (s->wi.z > 0.f) == (wo.z > 0.f);
            if (refl) {
                ++reflected;
                EXPECT_NEAR(glm::length(s->wi - vec3(-wo.x, -wo.y, wo.z)), 0.f, 1e-5f);
                EXPECT_NEAR(s->pdf, r, 1e-5);
            } else {
                // Snell: n_i sin_i = n_t sin_t, with eta = n_inside / n_outside.
                const float sin_o = safe_sqrt(1.f - wo.z * wo.z), sin_i = safe_sqrt(1.f - s->wi.z * s->wi.z);
                const float n_o = wo.z > 0.f ? 1.f : c.eta, n_i = wo.z > 0.f ? c.eta : 1.f;
                EXPECT_NEAR(n_o * sin_o, n_i * sin_i, 1e-5f);
                EXPECT_NEAR(glm::length(s->wi), 1.f, 1e-5f);
                EXPECT_NEAR(s->pdf, 1.0 - r, 1e-5);
            }
        }
        EXPECT_EQ(produced, n) << "cos " << c.cos_wo;
        if (r >= 1.0) {
            EXPECT_EQ(reflected, n) << "total internal reflection at cos " << c.cos_wo;
        } else {
            const double z = (reflected - n * r) / std::sqrt(n * r * (1 - r));
            EXPECT_LE(std::fabs(z), k) << "cos " << c.cos_wo << ": reflected " << reflected << " of " << n
                                       << ", Fresnel " << r;
        }
    }
    // Fresnel at normal incidence ((eta-1)/(eta+1))^2, 1 at grazing, symmetric in direction of travel at 0.
    EXPECT_NEAR(fresnel_dielectric(1.f, 1.5f), 0.04f, 1e-6f);
    EXPECT_NEAR(fresnel_dielectric(0.f, 1.5f), 1.f, 1e-6f);
    EXPECT_EQ(fresnel_dielectric(-0.5f, 1.5f), 1.f);  // beyond the critical angle from inside
}

// ---------------------------------------------------------------- consistency and reciprocity

std::vector<std::pair<std::string, Bsdf>> non_delta_bsdfs() {
    return {{"lambert", Lambertian{vec3(0.6f, 0.3f, 0.9f)}},
            {"ggx 0.05", Glossy{vec3(0.f), vec3(1.f), 0.05f}},
            {"ggx 0.2", Glossy{vec3(0.f), vec3(0.9f, 0.5f, 0.2f), 0.2f}},
            {"ggx 1", Glossy{vec3(0.f), vec3(1.f), 1.f}},
            {"diffuse+ggx", Glossy{vec3(0.5f, 0.2f, 0.1f), vec3(0.3f), 0.4f}}};
}

TEST(BsdfConsistency, SampleAgreesWithEvalAndPdf) {
    for (const auto& [name, b] : non_delta_bsdfs()) {
        Pcg32 g(5, 6);
        int checked = 0;
        for (int i = 0; i < 20000; ++i) {
            vec3 wo = square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
            const auto s = sample(b, wo, g.next_float(), vec2(g.next_float(), g.next_float()));
            if (!s) continue;
            ++checked;
            ASSERT_FALSE(s->is_delta);
            const vec3 f = eval(b, wo, s->wi);
            const float p = pdf(b, wo, s->wi);
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(s->f[c], f[c], 1e-5f * std::max(f[c], 1e-6f)) << name;
            ASSERT_NEAR(s->pdf, p, 1e-5f * p) << name;
            // The weight the integrator uses: f |cos| / pdf, finite.
            ASSERT_TRUE(is_finite(s->f * std::fabs(s->wi.z) / s->pdf)) << name;
        }
        EXPECT_GT(checked, 10000) << name;
    }
}

TEST(BsdfConsistency, ReflectionLobesAreReciprocal) {
    for (const auto& [name, b] : non_delta_bsdfs()) {
        Pcg32 g(8, 9);
        for (int i = 0; i < 10000; ++i) {
            const vec3 a = square_to_uniform_hemisphere(vec2(g.next_float(), g.next_float()));
            const vec3 c = square_to_uniform_hemisphere(vec2(g.next_float(), g.next_float()));
            const vec3 f1 = eval(b, a, c), f2 = eval(b, c, a);
            for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(f1[ch], f2[ch], 1e-4f * std::max(f1[ch], 1e-6f)) << name;
        }
    }
}

// ---------------------------------------------------------------- directional albedo

struct Albedo {
    test::Moments uniform, sampled;
};

// rho(wo) = E[f cos / pdf] by uniform-hemisphere sampling and by the BSDF's own sampling (luminance channel).
Albedo estimate_albedo(const Bsdf& b, vec3 wo, int n, uint64_t seed) {
    Albedo a;
    Pcg32 g(seed, 2 * seed + 1);
    for (int i = 0; i < n; ++i) {
        vec3 wi = square_to_uniform_hemisphere(vec2(g.next_float(), g.next_float()));
        if (wo.z < 0.f) wi.z = -wi.z;
        a.uniform.add(double(luminance(eval(b, wo, wi))) * std::fabs(wi.z) / uniform_hemisphere_pdf());
        const auto s = sample(b, wo, g.next_float(), vec2(g.next_float(), g.next_float()));
        double w = 0.0;
        if (s) w = double(luminance(s->f)) * std::fabs(s->wi.z) / s->pdf * sqr(s->eta);
        a.sampled.add(w);
    }
    return a;
}

TEST(BsdfAlbedo, AtMostOneAndTwoEstimatorsAgree) {
    const float cosines[] = {1.f, 0.5f, 0.1f, 1e-3f};
    auto bsdfs = non_delta_bsdfs();
    bsdfs.push_back({"lambert 1", Lambertian{vec3(1.f)}});
    bsdfs.push_back({"ggx 0.6 F=1", Glossy{vec3(0.f), vec3(1.f), 0.6f}});
    bsdfs.push_back({"diffuse 0.5 + ggx 0.5", Glossy{vec3(0.5f), vec3(0.5f), 0.3f}});
    // Family: 2 tests (bound, agreement) per BSDF and cosine.
    const double k = test::sidak_k(2.0 * double(bsdfs.size() * std::size(cosines)));
    for (const auto& [name, b] : bsdfs) {
        for (float c : cosines) {
            const Albedo a = estimate_albedo(b, dir_from_cos(c), 1 << 17, uint64_t(c * 1e4f) + name.size());
            const double se_u = a.uniform.stderr_of_mean(), se_s = a.sampled.stderr_of_mean();
            const std::string where = name + " at cos " + std::to_string(c) + ": uniform " +
                                      std::to_string(a.uniform.mean) + " +- " + std::to_string(se_u) + ", sampled " +
                                      std::to_string(a.sampled.mean) + " +- " + std::to_string(se_s);
            EXPECT_LE(a.sampled.mean, 1.0 + k * se_s + 1e-6) << where;
            EXPECT_LE(a.uniform.mean, 1.0 + k * se_u + 1e-6) << where;
            EXPECT_LE(std::fabs(a.uniform.mean - a.sampled.mean), k * std::sqrt(se_u * se_u + se_s * se_s) + 1e-6)
                << where;
            if (name == "lambert 1") {
                // Cosine sampling is exact for Lambert: every sample weighs 1 (zero variance).
                EXPECT_NEAR(a.sampled.mean, 1.0, 1e-5) << where;
                EXPECT_NEAR(a.sampled.variance(), 0.0, 1e-10) << where;
            }
        }
    }
}

// Delta lobes: the mirror's and the lossless glass's weights are exactly 1 per sample (glass: times eta^2, the
// radiance scaling across the interface, which the camera side undoes on the way out).
TEST(BsdfAlbedo, MirrorAndGlassAreExactlyOne) {
    const float cosines[] = {1.f, 0.5f, 0.1f, 1e-3f, -1.f, -0.5f, -0.1f, -1e-3f};
    const Bsdf bsdfs[] = {Mirror{vec3(1.f)}, Dielectric{1.5f}, Dielectric{1.f / 1.33f}};
    for (const Bsdf& b : bsdfs)
        for (float c : cosines) {
            const vec3 wo = dir_from_cos(c);
            Pcg32 g(17, 19);
            for (int i = 0; i < 2000; ++i) {
                const auto s = sample(b, wo, g.next_float(), vec2(g.next_float(), g.next_float()));
                ASSERT_TRUE(s.has_value()) << bsdf_type_name(b) << " cos " << c;
                const vec3 w = s->f * std::fabs(s->wi.z) / s->pdf * sqr(s->eta);
                for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(w[ch], 1.f, 1e-5f) << bsdf_type_name(b) << " cos " << c;
                EXPECT_EQ(eval(b, wo, s->wi), vec3(0.f));
                EXPECT_EQ(pdf(b, wo, s->wi), 0.f);
            }
        }
}

}  // namespace
}  // namespace pv
