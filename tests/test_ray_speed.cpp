// tests/test_ray_speed.cpp: what the ray-speed work (issue 13, docs/ray-speed.md) must not change: a texture kept
// as 8-bit codes looks up the same values as the floats they decode to, with the same repeat wrap at any uv; alpha
// cut-outs follow the renderer's edited materials (issue 10, item 5) with opaque and cut-out triangles split into
// two Embree geometries.
#include <gtest/gtest.h>

#include <cstring>

#include "core/renderer.h"
#include "core/rng.h"
#include "core/texture.h"
#include "support/scenes.h"

namespace pv {
namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Bilinear lookup with repeat wrap written out plainly (two modulo operations per coordinate), as Texture::lookup
// computed it before it skipped the divisions.
vec4 reference_lookup(const std::vector<vec4>& t, int w, int h, vec2 uv) {
    const float x = uv.x * float(w) - 0.5f, y = (1.f - uv.y) * float(h) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float tx = x - fx, ty = y - fy;
    auto wrap = [](long long i, int n) { return static_cast<size_t>(((i % n) + n) % n); };
    const long long ix = static_cast<long long>(fx), iy = static_cast<long long>(fy);
    const size_t x0 = wrap(ix, w), x1 = wrap(ix + 1, w), y0 = wrap(iy, h), y1 = wrap(iy + 1, h);
    const size_t W = size_t(w);
    return (1.f - ty) * ((1.f - tx) * t[y0 * W + x0] + tx * t[y0 * W + x1]) +
           ty * ((1.f - tx) * t[y1 * W + x0] + tx * t[y1 * W + x1]);
}

TEST(TextureStorage, EightBitCodesLookUpAsTheFloatsTheyDecodeTo) {
    const int w = 7, h = 5;  // odd sizes: wrapping is not a bit mask
    Pcg32 rng(3, 4);
    std::vector<vec4> texels(size_t(w) * size_t(h));
    for (vec4& t : texels)
        t = vec4(srgb_code_to_linear(int(rng.next_u32() % 256)), srgb_code_to_linear(int(rng.next_u32() % 256)),
                 srgb_code_to_linear(int(rng.next_u32() % 256)), float(rng.next_u32() % 256) / 255.f);
    const Texture coded(w, h, texels);
    EXPECT_EQ(coded.bytes(), texels.size() * 4) << "every texel is an 8-bit code: 4 bytes each";
    // Every one of the 256 codes in every channel is recognised.
    std::vector<vec4> all(256);
    for (int c = 0; c < 256; ++c)
        all[size_t(c)] =
            vec4(srgb_code_to_linear(c), srgb_code_to_linear(255 - c), srgb_code_to_linear(c), float(255 - c) / 255.f);
    EXPECT_EQ(Texture(16, 16, all).bytes(), all.size() * 4);
    // The same colours with one alpha that no byte gives: kept as floats.
    std::vector<vec4> odd = texels;
    odd[0].w = 0.3f;
    const Texture floats(w, h, odd);
    EXPECT_EQ(floats.bytes(), texels.size() * sizeof(vec4));

    for (int i = 0; i < 4000; ++i) {
        // Inside [0, 1), around it, far outside (negative and positive), and exactly on texel edges.
        const float span = i < 1000 ? 1.f : i < 2000 ? 4.f : 2e4f;
        vec2 uv((rng.next_float() - 0.25f) * span, (rng.next_float() - 0.25f) * span);
        if (i % 7 == 0) uv = vec2(float(i % w) / float(w), float(i % h) / float(h));
        const vec4 a = coded.lookup(uv), b = floats.lookup(uv), r = reference_lookup(texels, w, h, uv);
        for (int c = 0; c < 4; ++c) {
            EXPECT_TRUE(same_bits(a[c], r[c]))
                << "uv " << uv.x << "," << uv.y << " channel " << c << ": " << a[c] << " vs " << r[c];
            if (c < 3) {
                EXPECT_TRUE(same_bits(b[c], r[c])) << "float storage, uv " << uv.x << "," << uv.y;
            }
        }
    }
}

}  // namespace
}  // namespace pv

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

// Issue 10, item 5: the alpha filter read Scene::materials, so an edit through Renderer::set_materials (the viewer's
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
