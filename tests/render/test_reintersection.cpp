// tests/render/test_reintersection.cpp: self-intersection (after pbrt's Triangle.Reintersect): random
// triangles whose vertex coordinates are 10^U(-8,8); a ray from outside hits a random point, the hit point is
// reconstructed from Embree's barycentrics as the integrator does, and rays spawned from it (offset_ray_origin
// with the barycentric error bound; uniform directions and shadow-ray segments towards random points) must never
// hit the same triangle through Embree. This found two bugs: the fixed 256-ULP offset is smaller than p's own
// rounding error on slivers whose vertices are far larger than p, and Embree's default (non-robust) triangle test
// reports false hits on such slivers; core/base/math.h now takes an error bound and core/render/accel.cpp sets
// RTC_SCENE_FLAG_ROBUST. Both are needed: either alone leaves ~300 re-hits per bad sliver.
// Test kinds: regression
#include <gtest/gtest.h>

#include "core/render/accel.h"
#include "core/sampling/rng.h"
#include "core/sampling/warp.h"

namespace pv {
namespace {

float random_coordinate(Pcg32& g) {
    const float mag = std::pow(10.f, -8.f + 16.f * g.next_float());
    return (g.next_float() < 0.5f ? -1.f : 1.f) * mag * (0.5f + g.next_float());
}

// Returns the number of spawned rays that re-hit their own triangle, over `triangles` random triangles.
// scale_per_vertex: every coordinate gets its own magnitude (wild slivers); otherwise one magnitude per triangle.
int count_reintersections(int triangles, int rays_per_hit, bool scale_per_vertex, uint64_t seed, int* tested) {
    const ScopedFtzDaz ftz;  // the renderer's floating-point mode
    Pcg32 g(seed, 77);
    int rehits = 0;
    *tested = 0;
    for (int t = 0; t < triangles; ++t) {
        vec3 v[3];
        const float tri_scale = std::pow(10.f, -8.f + 16.f * g.next_float());
        const vec3 centre =
            scale_per_vertex ? vec3(0.f)
                             : tri_scale * vec3(g.next_float() * 4 - 2, g.next_float() * 4 - 2, g.next_float() * 4 - 2);
        for (vec3& p : v)
            for (int k = 0; k < 3; ++k)
                p[k] = scale_per_vertex ? random_coordinate(g) : centre[k] + tri_scale * (g.next_float() * 2 - 1);
        const vec3 c = glm::cross(v[1] - v[0], v[2] - v[0]);
        const float l0 = glm::length(v[1] - v[0]), l1 = glm::length(v[2] - v[0]);
        // Skip near-degenerate triangles (pbrt skips |cross|^2 < 1e-20 relative): normal must be well defined.
        if (!(glm::length(c) > 1e-6f * l0 * l1) || !is_finite(c)) continue;
        Scene scene;
        scene.materials.push_back(Material{});
        scene.add_triangle(v[0], v[1], v[2], 0);
        const Accel accel(scene);
        // A point on the triangle, reached by a ray from outside, reconstructed as the integrator does.
        const vec2 b = square_to_triangle(vec2(g.next_float(), g.next_float()));
        const vec3 target = (1.f - b.x - b.y) * v[0] + b.x * v[1] + b.y * v[2];
        const float size = std::max(l0, l1);
        const vec3 from = target + 2.f * size * square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
        Ray r;
        r.o = from;
        r.d = glm::normalize(target - from);
        Hit hit;
        if (!accel.intersect(r, hit)) continue;  // grazing miss of a sliver: nothing to spawn from
        ++*tested;
        const float b0 = 1.f - hit.u - hit.v;
        const vec3 p = b0 * v[0] + hit.u * v[1] + hit.v * v[2];
        const vec3 p_error = barycentric_error(v[0], v[1], v[2], b0, hit.u, hit.v);
        const vec3 ng = glm::normalize(c);
        for (int i = 0; i < rays_per_hit; ++i) {
            // Uniform directions, then rays towards random points (shadow-ray style, t in [0, 1 - 1e-4)).
            Ray s;
            const vec3 w = square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
            const float cw = glm::dot(w, ng);
            if (cw == 0.f) continue;  // exactly in the plane: the integrator never spawns these
            s.o = offset_ray_origin(p, cw > 0.f ? ng : -ng, p_error);
            s.d = w;
            Hit h2;
            if (accel.intersect(s, h2)) ++rehits;
            const vec3 q = target + size * 3.f * square_to_uniform_sphere(vec2(g.next_float(), g.next_float()));
            const float cq = glm::dot(q - p, ng);
            if (cq == 0.f) continue;
            Ray sh;
            sh.o = offset_ray_origin(p, cq > 0.f ? ng : -ng, p_error);
            sh.d = q - sh.o;
            sh.tmax = 1.f - 1e-4f;
            if (accel.occluded(sh)) ++rehits;
        }
    }
    return rehits;
}

TEST(Reintersection, RandomTrianglesOverSixteenDecades) {
    int tested = 0;
    const int rehits = count_reintersections(300, 500, false, 1, &tested);
    EXPECT_GT(tested, 250);
    EXPECT_EQ(rehits, 0) << "of " << tested << " triangles x 1000 rays";
}

TEST(Reintersection, RandomSliversWithPerVertexMagnitudes) {
    int tested = 0;
    const int rehits = count_reintersections(600, 300, true, 2, &tested);
    EXPECT_GT(tested, 50);
    EXPECT_EQ(rehits, 0) << "of " << tested << " triangles x 600 rays";
}

}  // namespace
}  // namespace pv
