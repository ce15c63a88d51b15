// tests/frame/test_convergence.cpp: the shipped sunlit room (assets/sunlit-room: lit only through its window) and the
// Russian roulette policy's unbiasedness there (issue 13). Bounds come from the sample variance with
// Sidak-corrected k (tests/support/stats.h); seeds are fixed.
// Test kinds: statistical
#include <gtest/gtest.h>

#include <filesystem>

#include "core/load/scene_file.h"
#include "support/scenes.h"
#include "support/stats.h"

namespace pv {
namespace {

std::shared_ptr<const Scene> sunlit_room() {
    static const auto scene = std::make_shared<const Scene>(load_scene(
        (std::filesystem::path(builtin_scene_path()).parent_path().parent_path() / "sunlit-room" / "scene.json")
            .string()));
    return scene;
}

RenderSettings independent(bool rr, uint32_t seed, int max_depth) {
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // the bounds use the i.i.d. sample variance
    s.russian_roulette = rr;
    s.seed = seed;
    s.max_depth = max_depth;
    return s;
}

TEST(SunlitRoom, LitOnlyThroughTheWindowFromInside) {
    const auto scene = sunlit_room();
    EXPECT_TRUE(scene->warnings.empty()) << scene->warnings.front();
    EXPECT_FALSE(scene->has_emitters());
    EXPECT_TRUE(scene->has_camera);
    // The camera is inside the room (x in [0, 4], y in [0, 2.7], z in [0, 5]).
    const vec3 eye = scene->camera.eye;
    EXPECT_TRUE(eye.x > 0.f && eye.x < 4.f && eye.y > 0.f && eye.y < 2.7f && eye.z > 0.f && eye.z < 5.f);
    const Image img = test::render_with_renderer(scene, scene->camera, independent(true, 1, 1024), 24, 18, 8).mean();
    test::expect_finite_and_lit(img);
    // Closed but for the window: rays leaving the eye in every direction of a sphere escape only through the
    // window's solid angle, well under a tenth of the sphere from here.
    const test::Tracer tracer(scene);
    int escaped = 0;
    const int n = 4096;
    for (int i = 0; i < n; ++i) {
        const float z = 1.f - 2.f * (float(i) + 0.5f) / float(n), r = std::sqrt(std::max(0.f, 1.f - z * z));
        const float phi = float(i) * 2.39996323f;  // golden angle: a spherical Fibonacci set
        Ray ray;
        ray.o = eye;
        ray.d = vec3(r * std::cos(phi), r * std::sin(phi), z);
        Hit hit;
        if (!tracer.accel().intersect(ray, hit)) ++escaped;
    }
    EXPECT_GT(escaped, 0);
    EXPECT_LT(escaped, n / 10);
}

// Roulette must not change the expectation: with the same depth cap, roulette on and off estimate exactly the same
// truncated sum, so their images must agree within the noise. Per pixel (Welch t, Sidak) and in total (|z| < 3.29).
TEST(SunlitRoom, RouletteAgreesWithNoRoulette) {
    const auto scene = sunlit_room();
    const int w = 16, h = 12, depth = 12;
    const auto on = test::PixelStats::from_film(
        test::render_with_renderer(scene, scene->camera, independent(true, 31, depth), w, h, 1024));
    const auto off = test::PixelStats::from_film(
        test::render_with_renderer(scene, scene->camera, independent(false, 32, depth), w, h, 512));
    const test::ImageComparison c = test::compare_images(on, off);
    EXPECT_TRUE(c.passed) << c.describe();
    EXPECT_GT(on.total_mean(), 0.01);
}

// assets/sunlit-room/window-sky.json: the same room under the sky alone, its window declared as a portal. The
// portal must lie in the opening: from the middle of the room, rays toward points across the portal (inset from its
// edges) leave the scene, and the sky is the only light.
TEST(SunlitRoom, WindowSkyPortalCoversTheWindow) {
    const auto scene = std::make_shared<const Scene>(load_scene(
        (std::filesystem::path(builtin_scene_path()).parent_path().parent_path() / "sunlit-room" / "window-sky.json")
            .string()));
    EXPECT_TRUE(scene->warnings.empty()) << scene->warnings.front();
    EXPECT_FALSE(scene->has_emitters());
    ASSERT_EQ(scene->portals.size(), 1u);
    const Portal& portal = scene->portals[0];
    const test::Tracer tracer(scene);
    const vec3 inside(2.f, 1.5f, 2.5f);
    for (float a : {0.05f, 0.5f, 0.95f})
        for (float b : {0.05f, 0.5f, 0.95f}) {
            Ray ray;
            ray.o = inside;
            ray.d = glm::normalize(portal.corner + a * portal.edge1 + b * portal.edge2 - inside);
            Hit hit;
            EXPECT_FALSE(tracer.accel().intersect(ray, hit)) << "portal point (" << a << ", " << b << ") is blocked";
        }
}

}  // namespace
}  // namespace pv
