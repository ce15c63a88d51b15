// core/render/surface.h: the geometry at a ray hit, reconstructed as every ray spawner needs it (the integrator, the
// ray benchmark and the robustness tests use this one definition): the point from Embree's barycentrics with its
// rounding-error bound, the geometric normal, and the interpolated shading normal.
#pragma once

#include <cmath>

#include "core/render/accel.h"
#include "core/scene/scene.h"

namespace pv {

struct SurfacePoint {
    vec3 p;        // reconstructed from barycentrics, not o + t d, whose error grows with t (Waechter and Binder)
    vec3 p_error;  // bound on p's rounding error (barycentric_error), for offset_ray_origin
    vec3 ng;       // unit geometric normal from the winding order
    vec3 ns;       // unit shading normal (interpolated vertex normals, else ng), on ng's side
    float b0;      // barycentric of vertex 0 (hit.u, hit.v are those of vertices 1 and 2)
};

// Starts loading the hit triangle's per-triangle records (vertex, normal and uv indices, material id), which live in
// separate arrays, so that their cache misses overlap instead of each waiting for the code that reads it (the
// material id is read only after the surface point is computed); with a packed record (TriangleRecord), that line
// and the normal indices. No effect on results.
[[gnu::always_inline]] inline void prefetch_hit(const Scene& s, const Hit& hit,
                                                const TriangleRecord* record = nullptr) {
    if (record) {
        __builtin_prefetch(record);
    } else {
        __builtin_prefetch(&s.triangles[hit.prim]);
        __builtin_prefetch(&s.material_ids[hit.prim]);
        if (!s.uv_indices.empty()) __builtin_prefetch(&s.uv_indices[hit.prim]);
    }
    if (!s.normal_indices.empty()) __builtin_prefetch(&s.normal_indices[hit.prim]);
}

// The surface point on the hit triangle with vertices p0, p1, p2 (the Scene's, or its packed record's copies).
[[gnu::always_inline]] inline SurfacePoint surface_point(const Scene& s, const Hit& hit, vec3 p0, vec3 p1, vec3 p2) {
    SurfacePoint sp;
    sp.b0 = 1.f - hit.u - hit.v;
    sp.p = sp.b0 * p0 + hit.u * p1 + hit.v * p2;
    sp.p_error = barycentric_error(p0, p1, p2, sp.b0, hit.u, hit.v);
    // Both normals are stored from the registers that computed the geometric one: copying sp.ng into sp.ns (or a
    // local into both) goes through memory, three 4-byte stores read back by one 8-byte load that waits for them
    // (a store-forwarding stall per vertex).
    const vec3 ng = safe_normalize(glm::cross(p1 - p0, p2 - p0));
    const float nx = ng.x, ny = ng.y, nz = ng.z;  // read one float at a time
    sp.ng = vec3(nx, ny, nz);
    sp.ns = vec3(nx, ny, nz);
    if (!s.normal_indices.empty()) {
        const uvec3 ni = s.normal_indices[hit.prim];
        if (ni.x != kNoIndex) {
            const vec3 n = sp.b0 * s.normals[ni.x] + hit.u * s.normals[ni.y] + hit.v * s.normals[ni.z];
            const float l2 = glm::dot(n, n);
            // A zero or NaN interpolated normal falls back to the geometric one (pbrt-v4, Triangle).
            vec3 ns = ng;
            if (l2 > 1e-12f && std::isfinite(l2)) ns = n / std::sqrt(l2);
            if (glm::dot(ns, ng) < 0.f) ns = -ns;
            sp.ns = ns;
        }
    }
    return sp;
}

// Always inlined: it is the first thing every path vertex does.
[[gnu::always_inline]] inline SurfacePoint surface_point(const Scene& s, const Hit& hit) {
    const uvec3 t = s.triangles[hit.prim];
    return surface_point(s, hit, s.positions[t.x], s.positions[t.y], s.positions[t.z]);
}

// The same from the triangle's packed record (the same values: the same bits).
[[gnu::always_inline]] inline SurfacePoint surface_point(const Scene& s, const Hit& hit, const TriangleRecord& r) {
    return surface_point(s, hit, r.p[0], r.p[1], r.p[2]);
}

// The normals a path vertex shades with, for a ray arriving from wo_world (front: wo_world on sf.ng's side): the
// integrator's and every other path walker's (the sky guide's training) one rule. Reflection lobes see the side wo
// is on; the dielectric (`bsdf`) needs the true orientation.
struct ShadingNormals {
    vec3 ng, ns;
};
[[gnu::always_inline]] inline ShadingNormals shading_normals(const SurfacePoint& sf, vec3 wo_world, bool front,
                                                             const Bsdf& bsdf) {
    const float eta = oriented_eta(bsdf);  // glass, or a solid transmissive metallic-roughness material
    const bool is_glass = eta != 0.f;
    vec3 ng = sf.ng, ns = sf.ns;
    if (!is_glass && !front) {
        ng = -ng;
        ns = -ns;
    }
    // Veach's rule: a direction must be on the same side of both normals; where the shading normal
    // would make wo back-facing, shade with the geometric normal instead.
    if ((glm::dot(wo_world, ns) > 0.f) != (glm::dot(wo_world, ng) > 0.f)) ns = ng;
    // Inside a dielectric, where the interpolated normal gives total internal reflection, the facet's own
    // normal. Interpolated normals are not reciprocal for glass: reflection about them keeps |p x d| about the
    // centre of a smooth-shaded sphere, so a path that once reflects totally inside can circle forever (0.9%
    // of the paths into a coarse sphere reached the depth cap). The facets make a true polyhedron, which light
    // leaves again (reversibility); refraction out and everything outside keep the smooth normals.
    if (is_glass && !front && ns != ng) {
        const float cos_o = glm::dot(wo_world, ns);
        if ((1.f - cos_o * cos_o) * eta * eta >= 1.f) ns = ng;
    }
    return {ng, ns};
}

}  // namespace pv
