// tests/frame/test_light_groups.cpp: light groups (core/render/light_groups.h, docs/light-groups.md).
//  * The groups of a scene: emissive materials (by light_group, else name), punctual lights, sky, sun; the cap of
//    kMaxLightGroups with "other" taking the rest.
//  * Keeping groups leaves the image unchanged, bit for bit (the film's sums with groups on equal those with them
//    off), the mix with every gain 1 is the film itself, bit for bit, and the groups add up to the image (to the
//    rounding of float path sums: each group's sum is accumulated apart from the image's).
//  * A gain k on a group is a render with that group's emission times k: the mixed image against an independent
//    render of the scaled scene, per-pixel Welch tests and the total mean's z (tests/support/stats.h), for an
//    emitter, the sky and the sun.
// Test kinds: statistical
#include <gtest/gtest.h>

#include <cstring>

#include "core/frame/renderer.h"
#include "core/render/light_groups.h"
#include "support/scenes.h"
#include "support/stats.h"

namespace pv {
namespace {

// The open box with its panel ("panel"), a second emitter ("lamp"), its sky and a sun: four groups.
std::shared_ptr<Scene> grouped_box() {
    auto scene = test::open_box(true);
    scene->materials.back().name = "panel";
    Material lamp;
    lamp.name = "lamp";
    lamp.emission = vec3(2.f, 1.f, 0.5f);
    const uint32_t m_lamp = test::add_material(*scene, lamp);
    test::add_quad(*scene, vec3(0.9f, 0.1f, -0.5f), vec3(0.9f, 0.1f, 0.5f), vec3(0.9f, 0.6f, 0.5f),
                   vec3(0.9f, 0.6f, -0.5f), m_lamp);
    scene->environment.sun_direction = glm::normalize(vec3(0.4f, 1.f, 0.6f));
    scene->environment.sun_angular_radius_deg = 3.f;
    scene->environment.sun_irradiance = vec3(2.f);
    return scene;
}

bool same_sums(const Film& a, const Film& b) {
    if (a.pixels().size() != b.pixels().size()) return false;
    for (size_t i = 0; i < a.pixels().size(); ++i) {
        const FilmPixel &p = a.pixels()[i], &q = b.pixels()[i];
        if (std::memcmp(p.sum, q.sum, sizeof p.sum) || std::memcmp(p.sum_sq, q.sum_sq, sizeof p.sum_sq) ||
            std::memcmp(p.sum_even, q.sum_even, sizeof p.sum_even) || p.n != q.n || p.n_even != q.n_even)
            return false;
    }
    return true;
}

Film render(std::shared_ptr<const Scene> scene, const RenderSettings& settings, bool groups, const LightGains& gains,
            int spp, const AdaptiveSettings& adaptive = {}, int* group_count = nullptr) {
    Renderer r(scene, 2);
    r.set_light_groups(groups);
    r.set_adaptive(adaptive);
    r.set_light_gains(gains);
    r.restart(scene->camera, settings, 24, 18);
    for (int i = 0; i < spp; ++i) r.render_pass();
    if (group_count) *group_count = r.light_group_count();
    return groups ? r.film() : r.film();
}

TEST(LightGroups, SceneGroups) {
    const auto scene = grouped_box();
    const TraceableScene ts(scene);
    const LightGroups& g = ts.light_groups();
    ASSERT_EQ(g.count(), 4);
    EXPECT_EQ(g.names, (std::vector<std::string>{"panel", "lamp", "sky", "sun"}));
    EXPECT_EQ(g.material[scene->materials.size() - 2], 0);
    EXPECT_EQ(g.material[scene->materials.size() - 1], 1);
    EXPECT_EQ(g.sky, 2);
    EXPECT_EQ(g.sun, 3);

    // A named group gathers its materials; past the cap the rest go to "other".
    auto many = std::make_shared<Scene>(*scene);
    many->materials[many->materials.size() - 1].light_group = "panel";
    EXPECT_EQ(TraceableScene(many).light_groups().count(), 3);
    for (int i = 0; i < 20; ++i) {
        Material m;
        m.name = "extra" + std::to_string(i);
        m.emission = vec3(1.f);
        test::add_material(*many, m);
    }
    const LightGroups capped = TraceableScene(many).light_groups();
    ASSERT_EQ(capped.count(), kMaxLightGroups);
    EXPECT_EQ(capped.names.back(), "other");
    EXPECT_EQ(capped.sky, kMaxLightGroups - 1);
    EXPECT_EQ(capped.sun, kMaxLightGroups - 1);
    EXPECT_EQ(capped.material.back(), kMaxLightGroups - 1);

    // One light: one group, and the film keeps nothing beside the image.
    auto single = test::open_box(false);
    EXPECT_EQ(TraceableScene(single).light_groups().count(), 1);
    int kept = -1;
    render(single, RenderSettings{}, true, {}, 1, {}, &kept);
    EXPECT_EQ(kept, 0);
}

// Every kind of contribution: emitters found by BSDF sampling and by NEE, the environment both ways (sky and sun
// split by direction), with and without MIS, the fog's medium vertices, and allocation's combined film.
TEST(LightGroups, ImageUnchangedAndGroupsAddUp) {
    struct Case {
        const char* name;
        bool mis, fog, allocate;
    };
    for (const Case& c : {Case{"mis", true, false, false}, Case{"nee without mis", false, false, false},
                          Case{"fog", true, true, false}, Case{"allocation", true, false, true}}) {
        SCOPED_TRACE(c.name);
        auto scene = grouped_box();
        if (c.fog) {
            scene->fog.sigma_s = vec3(0.2f);
            scene->fog.sigma_a = vec3(0.05f);
        }
        RenderSettings settings;
        settings.mis = c.mis;
        settings.seed = 3;
        AdaptiveSettings adaptive;
        adaptive.allocate = c.allocate;
        const int spp = c.allocate ? 24 : 8;
        int groups = 0;
        const Film with = render(scene, settings, true, {}, spp, adaptive, &groups);
        const Film without = render(scene, settings, false, {}, spp, adaptive);
        ASSERT_EQ(groups, 4);
        EXPECT_TRUE(same_sums(with, without));
        EXPECT_TRUE(same_sums(with.mixed(LightGains(4, vec3(1.f))), without));
        // The groups add up to the image, to float rounding of the path sums.
        double worst = 0.0;
        for (size_t i = 0; i < with.pixels().size(); ++i)
            for (int ch = 0; ch < 3; ++ch) {
                double sum = 0.0, even = 0.0;
                for (int g = 0; g < groups; ++g) {
                    sum += with.group(i, g).sum[ch];
                    even += with.group(i, g).sum_even[ch];
                }
                const FilmPixel& px = with.pixels()[i];
                worst = std::max(worst, std::fabs(sum - px.sum[ch]) / (px.sum[ch] + 1e-6));
                worst = std::max(worst, std::fabs(even - px.sum_even[ch]) / (px.sum_even[ch] + 1e-6));
            }
        EXPECT_LT(worst, 1e-5);
    }
}

// A gain on one group against the scene with that group's light scaled: equal within noise.
TEST(LightGroups, GainEqualsScaledEmission) {
    struct Case {
        const char* name;
        int group;
        vec3 k;
    };
    for (const Case& c : {Case{"emitter", 0, vec3(3.f)}, Case{"second emitter, coloured", 1, vec3(0.5f, 2.f, 1.f)},
                          Case{"sky", 2, vec3(0.25f)}, Case{"sun", 3, vec3(2.5f)}, Case{"muted sun", 3, vec3(0.f)}}) {
        SCOPED_TRACE(c.name);
        const auto scene = grouped_box();
        auto scaled = std::make_shared<Scene>(*scene);
        switch (c.group) {
            case 0:
                scaled->materials[scaled->materials.size() - 2].emission *= c.k;
                break;
            case 1:
                scaled->materials[scaled->materials.size() - 1].emission *= c.k;
                break;
            case 2:
                scaled->environment.strength *= c.k.x;
                break;
            default:
                scaled->environment.sun_irradiance *= c.k;
                break;
        }
        RenderSettings settings;
        settings.seed = 11;
        LightGains gains(4, vec3(1.f));
        gains[size_t(c.group)] = c.k;
        const Film mixed = render(scene, settings, true, gains, 256).mixed(gains);
        settings.seed = 12;  // independent of the mix's samples
        const Film reference = render(scaled, settings, false, {}, 256);
        const test::ImageComparison cmp =
            test::compare_images(test::PixelStats::from_film(mixed), test::PixelStats::from_film(reference));
        EXPECT_TRUE(cmp.passed) << cmp.describe();
    }
}

}  // namespace
}  // namespace pv
