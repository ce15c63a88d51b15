// tests/render/test_alpha_edits.cpp: alpha cut-outs follow the renderer's edited materials (Renderer::set_materials,
// the viewer's material panel), shadow rays included, with opaque and cut-out triangles in two Embree geometries
// whose hits still name the Scene's triangles.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cstring>

#include "core/frame/renderer.h"
#include "core/sampling/rng.h"
#include "core/scene/texture.h"
#include "support/scenes.h"

namespace pv {
namespace {

// A 1x1 texture of opacity `alpha` (an alpha cut-out that lets light through in proportion 1 - alpha).
Texture opacity(float alpha) { return Texture(1, 1, {vec4(1.f, 1.f, 1.f, alpha)}); }

// A unit quad at z = 1 facing -z (material `occluder`) over the origin, and a ray up through it.
std::shared_ptr<Scene> occluder_scene(uint32_t occluder_alpha) {
    auto scene = std::make_shared<Scene>();
    scene->textures.push_back(opacity(0.f));  // fully transparent
    Material m;
    m.name = "occluder";
    m.alpha_texture = occluder_alpha;
    scene->materials.push_back(m);
    test::add_quad(*scene, vec3(-1, -1, 1), vec3(-1, 1, 1), vec3(1, 1, 1), vec3(1, -1, 1), 0);
    return scene;
}

Ray up_from_origin() {
    Ray r;
    r.o = vec3(0.1f, 0.2f, 0.f);
    r.d = vec3(0.f, 0.f, 1.f);
    return r;
}

// The alpha filter once read Scene::materials, so an edit through Renderer::set_materials (the viewer's
// material panel) never reached any ray, shadow rays included. Failed before the fix: the edited occluder stayed
// transparent (first test) or opaque (second).
TEST(AlphaEdits, RemovingACutOutMakesTheSurfaceBlockRays) {
    Renderer renderer(occluder_scene(0), 1);
    const ScopedFtzDaz ftz;
    Hit hit;
    ASSERT_FALSE(renderer.traceable().accel().occluded(up_from_origin()))
        << "a fully transparent cut-out lets rays through";
    ASSERT_FALSE(renderer.traceable().accel().intersect(up_from_origin(), hit));
    std::vector<Material> edited = renderer.traceable().materials();
    edited[0].alpha_texture = kNoIndex;
    renderer.set_materials(edited);
    EXPECT_TRUE(renderer.traceable().accel().occluded(up_from_origin()))
        << "shadow rays must see the edited, opaque occluder";
    EXPECT_TRUE(renderer.traceable().accel().intersect(up_from_origin(), hit));
    EXPECT_NEAR(hit.t, 1.f, 1e-6f);
}

TEST(AlphaEdits, AddingACutOutLetsRaysThrough) {
    Renderer renderer(occluder_scene(kNoIndex), 1);
    const ScopedFtzDaz ftz;
    Hit hit;
    ASSERT_TRUE(renderer.traceable().accel().occluded(up_from_origin()));
    std::vector<Material> edited = renderer.traceable().materials();
    edited[0].alpha_texture = 0;
    renderer.set_materials(edited);
    EXPECT_FALSE(renderer.traceable().accel().occluded(up_from_origin())) << "shadow rays must pass the edited cut-out";
    EXPECT_FALSE(renderer.traceable().accel().intersect(up_from_origin(), hit));
    // And back: opaque again.
    edited[0].alpha_texture = kNoIndex;
    renderer.set_materials(edited);
    EXPECT_TRUE(renderer.traceable().accel().occluded(up_from_origin()));
}

// Triangles of materials with and without a cut-out go to separate Embree geometries; hits still name the Scene's
// triangle, whichever geometry it is in and in whatever order the two kinds are interleaved.
TEST(AlphaEdits, SplitGeometryReportsSceneTriangles) {
    Scene scene;
    scene.textures.push_back(opacity(1.f));  // a cut-out that keeps everything: the filter runs and keeps the hit
    Material opaque, cut;
    cut.alpha_texture = 0;
    scene.materials = {opaque, cut};
    const int n = 9;
    for (int i = 0; i < n; ++i) {
        const float x = 3.f * float(i);
        test::add_quad(scene, vec3(x, -1, 1), vec3(x, 1, 1), vec3(x + 2, 1, 1), vec3(x + 2, -1, 1),
                       uint32_t(i % 3 == 1));
    }
    const Accel accel(scene);
    const ScopedFtzDaz ftz;
    for (uint32_t t = 0; t < uint32_t(scene.triangle_count()); ++t) {
        const uvec3 v = scene.triangles[t];
        Ray r;
        r.o = (scene.positions[v.x] + scene.positions[v.y] + scene.positions[v.z]) / 3.f - vec3(0, 0, 1);
        r.d = vec3(0, 0, 1);
        Hit hit;
        ASSERT_TRUE(accel.intersect(r, hit)) << "triangle " << t;
        EXPECT_EQ(hit.prim, t);
    }
}

}  // namespace
}  // namespace pv
