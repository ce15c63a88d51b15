// tests/scene/test_bsdf_layers.cpp: the layers over glTF's metallic-roughness base (core/scene/bsdf_pbr.h):
// KHR_materials_clearcoat's coat and KHR_materials_sheen's Charlie sheen, layered by albedo scaling.
//  * chi-square of sample() against pdf() for each layer over several bases (smooth and rough coat, wo on both sides,
//    a solid's inside), and sample() agrees with eval() and pdf();
//  * white furnace: a white base under a white coat (clearcoat 1) and/or a white sheen (sheen colour 1) reflects 1,
//    within the albedo tables' interpolation error + k sigma;
//  * the layers are present only when asked for, and a texel scales their factors keeping the lobes.
// Test kinds: analytic; statistical: Chi2MetallicRoughnessLayers
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "core/sampling/warp.h"
#include "core/scene/bsdf.h"
#include "core/scene/sheen.h"
#include "tests/support/chi2.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

using test::chi2_test;
using test::Chi2Options;

vec3 dir_from_cos(float cos_theta, float phi = 0.7f) {
    const float s = safe_sqrt(1.f - cos_theta * cos_theta);
    return vec3(s * std::cos(phi), s * std::sin(phi), cos_theta);
}

struct Layering {
    float clearcoat = 0.f, clearcoat_roughness = 0.f;
    vec3 sheen_color{0.f};
    float sheen_roughness = 0.f;
};

MetallicRoughness layered(vec3 base, float metallic, float roughness, const Layering& l, float transmission = 0.f,
                          bool thin = true) {
    MetallicRoughness m;
    m.base_color = base;
    m.metallic = metallic;
    m.roughness = roughness;
    m.transmission = transmission;
    m.thin_walled = thin;
    m.clearcoat = l.clearcoat;
    m.clearcoat_roughness = l.clearcoat_roughness;
    m.sheen_color = l.sheen_color;
    m.sheen_roughness = l.sheen_roughness;
    return make_metallic_roughness(m);
}

struct Case {
    std::string name;
    MetallicRoughness m;
    float cos_wo;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::vector<Case> cases() {
    const vec3 base(0.8f, 0.6f, 0.3f);
    const Layering coat_rough{1.f, 0.3f}, coat_smooth{0.7f, 0.f}, coat_wide{0.5f, 0.9f};
    const Layering sheen{0.f, 0.f, vec3(0.9f, 0.5f, 0.7f), 0.5f}, sheen_sharp{0.f, 0.f, vec3(1.f), 0.15f};
    const Layering both{0.8f, 0.2f, vec3(0.6f, 0.8f, 1.f), 0.7f};
    return {
        {"coat_rough_over_plastic_cos0_8", layered(base, 0.f, 0.6f, coat_rough), 0.8f},
        {"coat_rough_over_plastic_back_cos_0_4", layered(base, 0.f, 0.6f, coat_rough), -0.4f},
        {"coat_smooth_over_rough_metal_cos0_5", layered(base, 1.f, 0.5f, coat_smooth), 0.5f},
        {"coat_wide_over_smooth_plastic_cos0_1", layered(base, 0.f, 0.f, coat_wide), 0.1f},
        {"coat_rough_over_thin_transmission_cos0_6", layered(base, 0.f, 0.4f, coat_rough, 0.7f), 0.6f},
        {"coat_rough_over_solid_cos0_7", layered(base, 0.f, 0.4f, coat_rough, 1.f, false), 0.7f},
        {"coat_rough_over_solid_inside_cos_0_6", layered(base, 0.f, 0.4f, coat_rough, 1.f, false), -0.6f},
        {"sheen_over_plastic_cos0_9", layered(base, 0.f, 0.7f, sheen), 0.9f},
        {"sheen_over_metal_cos0_3", layered(base, 1.f, 0.3f, sheen), 0.3f},
        {"sheen_sharp_over_plastic_cos0_2", layered(base, 0.f, 0.8f, sheen_sharp), 0.2f},
        {"sheen_and_coat_over_metal_cos0_6", layered(base, 0.6f, 0.5f, both), 0.6f},
        {"sheen_and_coat_over_smooth_metal_cos_0_3", layered(base, 1.f, 0.f, both), -0.3f},
    };
}

class Chi2MetallicRoughnessLayers : public testing::TestWithParam<Case> {};

TEST_P(Chi2MetallicRoughnessLayers, SamplesFollowPdf) {
    const Case c = GetParam();
    const Bsdf b = c.m;
    ASSERT_FALSE(is_delta(b));
    const vec3 wo = dir_from_cos(c.cos_wo);
    Chi2Options o;
    o.test_count = double(cases().size());
    o.ires = 4;
    o.seed = std::hash<std::string>()(c.name) | 1;
    const auto r = chi2_test(
        [&](Pcg32& g) -> std::optional<vec3> {
            const float ul = g.next_float();
            const vec2 u(g.next_float(), g.next_float());
            const auto s = sample(b, wo, ul, u);
            if (!s || s->is_delta || !(s->pdf > 0.f) || is_black(s->f)) return std::nullopt;
            return s->wi;
        },
        [&](vec3 wi) { return double(pdf(b, wo, wi)); }, o);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.sampled_fraction, r.pdf_integral, 5e-3) << r.message;
}

INSTANTIATE_TEST_SUITE_P(Layers, Chi2MetallicRoughnessLayers, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<Case>& i) { return i.param.name; });

TEST(MetallicRoughnessLayers, SampleAgreesWithEvalAndPdf) {
    for (const Case& c : cases()) {
        const Bsdf b = c.m;
        Pcg32 g(5, 6);
        int checked = 0, delta = 0;
        for (int i = 0; i < 4000; ++i) {
            const vec3 wo = square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
            const auto s = sample(b, wo, g.next_float(), vec2(g.next_float(), g.next_float()));
            if (!s) continue;
            ASSERT_TRUE(is_finite(s->f * std::fabs(s->wi.z) / s->pdf)) << c.name;
            if (s->is_delta) {
                ++delta;
                ASSERT_LE(s->pdf, 1.f) << c.name;
                continue;
            }
            ++checked;
            const vec3 f = eval(b, wo, s->wi);
            const float p = pdf(b, wo, s->wi);
            for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(s->f[ch], f[ch], 1e-5f * std::max(f[ch], 1e-6f)) << c.name;
            ASSERT_NEAR(s->pdf, p, 1e-5f * p) << c.name;
        }
        EXPECT_GT(checked, 1000) << c.name;
        EXPECT_GT(checked + delta, 2000) << c.name;
    }
}

// The white furnace with layers: a white base (metallic 0 and 1, roughness 0, 0.5, 1) under a white coat (clearcoat 1,
// coat roughness 0, 0.3, 1), a white sheen (sheen colour 1, sheen roughness 0.3, 1), or both, reflects 1 at
// mu_o = 1, 0.5, 0.15 (estimated by the BSDF's own sampling, 2^18 samples each: a sharp sheen sampled by the cosine
// needs them near grazing). The bound: 1% + k sigma (k: Sidak
// over every estimate), 1% being the tables' interpolation error: the base's (< 0.1%: WhiteSphereRingsAreOne), the
// coat's (the GGX tables, bilinear: < 1%, GgxDielectricTableMatchesMonteCarlo) and the sheen's (bilinear on 16 x 16,
// within 0.01 of quadrature: Sheen.AlbedoTableMatchesQuadrature).
TEST(MetallicRoughnessLayers, WhiteFurnaceIsOne) {
    std::vector<std::pair<std::string, Layering>> layerings;
    for (float cr : {0.f, 0.3f, 1.f}) layerings.push_back({"coat r " + std::to_string(cr), {1.f, cr}});
    for (float sr : {0.3f, 1.f}) layerings.push_back({"sheen r " + std::to_string(sr), {0.f, 0.f, vec3(1.f), sr}});
    layerings.push_back({"coat r 0.2 + sheen r 0.5", {1.f, 0.2f, vec3(1.f), 0.5f}});
    const float cosines[] = {1.f, 0.5f, 0.15f};
    const float roughnesses[] = {0.f, 0.5f, 1.f};
    const double k = test::sidak_k(double(layerings.size() * 2 * std::size(roughnesses) * std::size(cosines)));
    double lowest = 2.0, highest = 0.0;
    for (const auto& [name, l] : layerings)
        for (float metallic : {0.f, 1.f})
            for (float roughness : roughnesses) {
                const Bsdf b = layered(vec3(1.f), metallic, roughness, l);
                for (float c : cosines) {
                    Pcg32 g(uint64_t(1000.f * c) + 7, uint64_t(100.f * roughness + 10.f * metallic) + name.size());
                    test::Moments a;
                    const vec3 wo = dir_from_cos(c);
                    for (int i = 0; i < (1 << 18); ++i) {
                        const auto s = sample(b, wo, g.next_float(), vec2(g.next_float(), g.next_float()));
                        const vec3 w = s ? s->f * std::fabs(s->wi.z) / s->pdf : vec3(0.f);
                        a.add((double(w.x) + double(w.y) + double(w.z)) / 3.0);
                    }
                    const std::string where = name + ", metallic " + std::to_string(metallic) + " roughness " +
                                              std::to_string(roughness) + " mu " + std::to_string(c) + ": " +
                                              std::to_string(a.mean) + " +- " + std::to_string(a.stderr_of_mean());
                    EXPECT_LT(k * a.stderr_of_mean(), 0.01) << where;
                    EXPECT_NEAR(a.mean, 1.0, 0.01 + k * a.stderr_of_mean()) << where;
                    lowest = std::min(lowest, a.mean);
                    highest = std::max(highest, a.mean);
                }
            }
    std::cout << "white furnace with layers: " << lowest << " .. " << highest << "\n";
}

// The layers are lobes only when asked for; without them the material is what it was (same lobes, same delta-ness);
// a smooth coat over a smooth metal is a delta material, a rough coat or a sheen is not.
TEST(MetallicRoughnessLayers, OnlyWhenAskedFor) {
    using L = MetallicRoughness;
    const MetallicRoughness plain = layered(vec3(0.5f), 0.f, 0.5f, {});
    EXPECT_FALSE(plain.layered());
    EXPECT_EQ(plain.lobes, L::kDiffuse | L::kSpecular);
    EXPECT_EQ(layered(vec3(0.5f), 0.f, 0.5f, {0.5f, 0.2f}).lobes, L::kDiffuse | L::kSpecular | L::kClearcoat);
    EXPECT_EQ(layered(vec3(0.5f), 0.f, 0.5f, {0.f, 0.f, vec3(0.f, 0.1f, 0.f), 0.5f}).lobes,
              L::kDiffuse | L::kSpecular | L::kSheen);
    EXPECT_TRUE(is_delta(layered(vec3(1.f), 1.f, 0.f, {1.f, 0.f})));
    EXPECT_FALSE(is_delta(layered(vec3(1.f), 1.f, 0.f, {1.f, 0.1f})));
    EXPECT_FALSE(is_delta(layered(vec3(1.f), 1.f, 0.f, {0.f, 0.f, vec3(1.f), 0.5f})));
    // A solid's inside sees no layer: exactly the unlayered material there.
    const Bsdf solid = layered(vec3(0.9f), 0.f, 0.4f, {1.f, 0.3f, vec3(1.f), 0.5f}, 1.f, false);
    const Bsdf bare = layered(vec3(0.9f), 0.f, 0.4f, {}, 1.f, false);
    Pcg32 g(3, 4);
    for (int i = 0; i < 500; ++i) {
        vec3 wo = square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
        wo.z = -std::fabs(wo.z);
        const vec3 wi = square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
        EXPECT_EQ(eval(solid, wo, wi), eval(bare, wo, wi));
    }
}

// Texels scale the layers' factors and keep the lobes (a texel roughness 0 on a rough coat stays a GGX lobe).
TEST(MetallicRoughnessLayers, TexelsScaleFactorsAndKeepLobes) {
    const MetallicRoughness base = layered(vec3(0.7f), 0.3f, 0.6f, {0.8f, 0.5f, vec3(0.5f, 0.6f, 0.7f), 0.6f});
    MetallicRoughness t = base;
    apply_clearcoat_texel(t, 0.5f, 0.f);
    apply_sheen_texel(t, vec3(1.f, 0.5f, 0.f), 0.5f);
    EXPECT_EQ(t.clearcoat, 0.4f);
    EXPECT_EQ(t.coat_alpha, kMinAlpha);
    EXPECT_EQ(t.sheen_color, vec3(0.5f, 0.3f, 0.f));
    EXPECT_EQ(t.sheen_roughness, 0.3f);
    EXPECT_EQ(t.lobes, base.lobes);
    EXPECT_FALSE(is_delta(t));
}

}  // namespace
}  // namespace pv
