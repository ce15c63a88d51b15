// tests/render/test_hit_layout.cpp: the packed per-triangle hit records (core/scene/scene.h: TriangleRecord,
// pack_triangles) hold exactly the Scene's data, and what the path tracer computes from them (surface point, uv,
// material) is the same, bit for bit, as from the Scene's indexed arrays.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cstring>

#include "core/render/surface.h"
#include "core/render/traceable_scene.h"
#include "core/sampling/rng.h"
#include "tests/support/scenes.h"

namespace pv {
namespace {

template <typename T>
bool same_bits(const T& a, const T& b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// Triangles with shared and unshared vertices, several materials, uvs on some triangles and none on others
// (kNoIndex), and shading normals on some.
Scene mixed_scene() {
    Scene s;
    Material a, b, c;
    test::add_material(s, a);
    test::add_material(s, b);
    test::add_material(s, c);
    test::add_icosphere(s, vec3(0.3f, -1.7f, 2.f), 1.25f, 2, 1);
    test::add_quad(s, vec3(-3, 0, -3), vec3(-3, 0, 3), vec3(3, 0, 3), vec3(3, 0, -3), 2);
    s.add_triangle(vec3(1e-3f, 5.f, 7.f), vec3(1e3f, 5.5f, 7.f), vec3(0.5f, -4.f, 1e4f), 0);
    Pcg32 rng(3, 1);
    for (int i = 0; i < 40; ++i) s.uvs.push_back(vec2(rng.next_float() * 9.f - 4.f, rng.next_float() * 3.f - 1.f));
    for (int i = 0; i < 12; ++i) s.normals.push_back(glm::normalize(vec3(rng.next_float() - 0.5f, 1.f, 0.3f)));
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        const auto pick = [&](size_t n) { return uint32_t(rng.next_float() * float(n)) % uint32_t(n); };
        s.uv_indices.push_back(t % 3 == 1 ? uvec3(kNoIndex) : uvec3(pick(40), pick(40), pick(40)));
        s.normal_indices.push_back(t % 2 == 0 ? uvec3(kNoIndex) : uvec3(pick(12), pick(12), pick(12)));
    }
    return s;
}

TEST(HitLayout, RecordsHoldTheScenesVerticesUvsAndMaterials) {
    const Scene s = mixed_scene();
    const std::vector<TriangleRecord> records = pack_triangles(s);
    ASSERT_EQ(records.size(), s.triangle_count());
    size_t without_uv = 0;
    for (size_t t = 0; t < records.size(); ++t) {
        const TriangleRecord& r = records[t];
        EXPECT_EQ(reinterpret_cast<uintptr_t>(&r) % 64, 0u);  // one cache line each
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(same_bits(r.p[k], s.positions[s.triangles[t][k]])) << t;
        EXPECT_EQ(r.material(), s.material_ids[t]);
        const bool has_uv = s.uv_indices[t].x != kNoIndex;
        EXPECT_EQ((r.material_and_flags & TriangleRecord::kNoUv) == 0, has_uv);
        without_uv += !has_uv;
        if (has_uv) {
            for (int k = 0; k < 3; ++k) EXPECT_TRUE(same_bits(r.uv[k], s.uvs[s.uv_indices[t][k]])) << t;
        }
    }
    EXPECT_GT(without_uv, 0u);
    EXPECT_LT(without_uv, records.size());
}

TEST(HitLayout, RecordsGiveTheSameSurfacePointAndUvBitForBit) {
    const Scene s = mixed_scene();
    const std::vector<TriangleRecord> records = pack_triangles(s);
    ASSERT_EQ(records.size(), s.triangle_count());
    Pcg32 rng(11, 1);
    for (uint32_t t = 0; t < s.triangle_count(); ++t)
        for (int i = 0; i < 8; ++i) {
            Hit hit;
            hit.prim = t;
            // Inside the triangle, on its edges and corners (0 and 1 exactly).
            hit.u = i == 0 ? 0.f : i == 1 ? 1.f : rng.next_float();
            hit.v = i < 2 ? 0.f : i == 2 ? 1.f - hit.u : rng.next_float() * (1.f - hit.u);
            const SurfacePoint a = surface_point(s, hit), b = surface_point(s, hit, records[t]);
            EXPECT_TRUE(same_bits(a.p, b.p) && same_bits(a.p_error, b.p_error) && same_bits(a.ng, b.ng) &&
                        same_bits(a.ns, b.ns) && same_bits(a.b0, b.b0))
                << "triangle " << t;
            EXPECT_TRUE(same_bits(s.uv_at(t, hit.u, hit.v), records[t].uv_at(hit.u, hit.v))) << "triangle " << t;
        }
}

TEST(HitLayout, SceneWithoutUvsPacksZeroUvs) {
    Scene s;
    test::add_material(s, Material{});
    test::add_quad(s, vec3(0, 0, 0), vec3(1, 0, 0), vec3(1, 1, 0), vec3(0, 1, 0), 0);
    ASSERT_TRUE(s.uv_indices.empty());
    const std::vector<TriangleRecord> records = pack_triangles(s);
    ASSERT_EQ(records.size(), 2u);
    for (uint32_t t = 0; t < 2; ++t) {
        EXPECT_TRUE(same_bits(records[t].uv_at(0.25f, 0.5f), s.uv_at(t, 0.25f, 0.5f)));
        EXPECT_EQ(records[t].material(), 0u);
    }
}

TEST(HitLayout, NothingPackedAboveTheTriangleLimit) {
    const Scene s = mixed_scene();
    EXPECT_TRUE(pack_triangles(s, s.triangle_count() - 1).empty());
    EXPECT_EQ(pack_triangles(s, s.triangle_count()).size(), s.triangle_count());
    // 64 bytes a triangle: at the limit, 64 MiB.
    EXPECT_EQ(kMaxPackedTriangles * sizeof(TriangleRecord), size_t(64) << 20);
}

TEST(HitLayout, TraceableSceneHandsOutTheRecordOfEachTriangle) {
    auto scene = std::make_shared<Scene>(mixed_scene());
    const TraceableScene ts(scene);
    const std::vector<TriangleRecord> records = pack_triangles(*scene);
    for (uint32_t t = 0; t < scene->triangle_count(); ++t) {
        const TriangleRecord* r = ts.triangle_record(t);
        ASSERT_NE(r, nullptr);
        EXPECT_TRUE(same_bits(*r, records[t]));
        EXPECT_EQ(&ts.materials()[r->material()], &ts.material(t));
    }
}

}  // namespace
}  // namespace pv
