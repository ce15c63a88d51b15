// tests/render/test_degenerate_geometry.cpp: degenerate, sliver and huge triangles: the loader drops and counts them
// and the render stays finite; a zero-area emitter is never sampled; rays beyond Embree's coordinate range hit
// nothing instead of aborting.
// Test kinds: regression
#include <gtest/gtest.h>

#include "core/frame/renderer.h"
#include "core/load/obj_loader.h"
#include "core/render/lights.h"
#include "core/sampling/warp.h"
#include "core/scene/bsdf.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

// ---------------------------------------------------------------- degenerate geometry

TEST(DegenerateGeometry, LoaderDropsAndCountsAndRenderStaysFinite) {
    const std::string obj = R"(v 0 0 0
v 1 0 0
v 2 0 0
v 0 1 0
v 1e-7 0 0
v 0 0 1
v 1e19 0 0
v 0 1e18 0
v 1 1e18 0
v 1 -1 0
f 1 2 3
f 1 1 4
f 1 5 4
f 1 4 6
f 1 7 4
f 2 8 9
f 1 2 10
)";
    // 1 2 3 collinear and 1 1 4 coincident: zero area. 1 5 4: sliver (aspect 1e7), kept. 1 4 6: fine.
    // 1 7 4: a vertex beyond 1.844e18, dropped as non-finite. 2 8 9: at 1e18, kept or dropped, never NaN.
    const Scene s = load_obj_from_string(obj, "degenerate.obj");
    EXPECT_EQ(s.stats.dropped_degenerate + s.stats.dropped_nonfinite + s.triangles.size(), 7u);
    EXPECT_GE(s.stats.dropped_degenerate, 2u);
    EXPECT_EQ(s.stats.dropped_nonfinite, 1u);
    EXPECT_GE(s.triangles.size(), 3u);
    bool warned = false;
    for (const std::string& w : s.warnings) warned |= w.find("zero-area") != std::string::npos;
    EXPECT_TRUE(warned);
    auto scene = std::make_shared<Scene>(s);
    scene->environment.background = vec3(1.f);
    CameraDesc cam;
    cam.eye = vec3(0.5f, 0.3f, 3.f);
    cam.target = vec3(0.3f, 0.3f, 0.f);
    uint64_t dropped = 0;
    const Film film = test::render_with_renderer(scene, cam, RenderSettings{}, 16, 16, 8, 2, &dropped);
    EXPECT_EQ(dropped, 0u);
    const Image img = film.mean();
    for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v));
}

TEST(DegenerateGeometry, ZeroAreaEmitterIsNeverSampled) {
    Scene scene;
    Material light;
    light.emission = vec3(10.f);
    scene.materials.push_back(light);
    scene.add_triangle(vec3(0, 1, 0), vec3(1, 1, 0), vec3(2, 1, 0), 0);  // collinear
    scene.add_triangle(vec3(3, 1, 3), vec3(3, 1, 3), vec3(3, 2, 3), 0);  // coincident vertices
    scene.add_triangle(vec3(0, 2, 0), vec3(0, 2, 1), vec3(1, 2, 0), 0);  // a real light, facing down
    const LightSet lights(scene, scene.materials);
    EXPECT_EQ(lights.size(), 1u);
    EXPECT_EQ(lights.pmf(0), 0.f);
    EXPECT_EQ(lights.pmf(1), 0.f);
    EXPECT_EQ(lights.pmf(2), 1.f);
    Pcg32 g(1, 2);
    for (int i = 0; i < 100000; ++i) {
        LightSample s;
        ASSERT_TRUE(
            lights.sample(vec3(0.2f, 0.f, 0.2f), vec3(0.f), g.next_float(), vec2(g.next_float(), g.next_float()), s));
        ASSERT_NEAR(s.p.y, 2.f, 1e-6f);
        ASSERT_TRUE(std::isfinite(s.pdf));
    }
}

// Vertices up to 1.844e18 are valid, but a camera framing them (or any ray) can land beyond Embree's coordinate
// range, where Debian's Embree asserts and aborts (found by the fuzzer: `pathview render` of such an OBJ aborted).
// Such rays must simply hit nothing.
TEST(DegenerateGeometry, RaysBeyondEmbreeRangeHitNothingInsteadOfAborting) {
    auto scene = std::make_shared<Scene>(load_obj_from_string("v 0 0 0\nv 1 0 0\nv 0 1 1.8e18\nf 1 2 3\n", "far.obj"));
    ASSERT_EQ(scene->triangles.size(), 1u);
    const CameraDesc cam = scene->framing_camera();
    EXPECT_GT(max_component(glm::abs(cam.eye)), 1.844e18f);  // the case being tested
    uint64_t dropped = 0;
    const Film film = test::render_with_renderer(scene, cam, RenderSettings{}, 8, 8, 2, 1, &dropped);
    EXPECT_EQ(dropped, 0u);
    for (float v : film.mean().rgb) EXPECT_TRUE(std::isfinite(v));
    const Accel accel(*scene);
    Hit hit;
    Ray r;
    r.d = vec3(0.f, 0.f, -1.f);
    for (vec3 o : {vec3(0.f, 0.f, 1e20f), vec3(std::numeric_limits<float>::infinity()), vec3(std::nanf(""))}) {
        r.o = o;
        EXPECT_FALSE(accel.intersect(r, hit));
        EXPECT_FALSE(accel.occluded(r));
    }
    r.o = vec3(0.2f, 0.2f, 1.7e18f);  // just inside the range: still traced
    r.d = vec3(0.f, 0.f, -1.f);
    EXPECT_TRUE(accel.intersect(r, hit));
}

}  // namespace
}  // namespace pv
