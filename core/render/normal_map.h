// core/render/normal_map.h: a glTF normalTexture applied to a surface point's shading normal (called through
// core/render/shading.h's apply_normal_map by the integrator, the AOV pass and the sky guide's training; materials
// without a normal map never reach it).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/render/surface.h"
#include "core/scene/scene.h"

namespace pv {

// The shading normal a normal-map texel (linear, in [0, 1]^3) gives on triangle `prim` at barycentrics (u, v):
// n = normalize(T x scale + B y scale + N z), (x, y, z) = 2 texel - 1, N the surface point's shading normal.
// T and B: the file's TANGENT interpolated (B = w cross(N, T)), else the triangle's dp/du and dp/dv from its set-0
// uvs (pathview's v-up uvs: B points up the image, as glTF's tangent space has it), else (no uvs, or degenerate
// ones) any frame about N. The result is on ng's side, like every shading normal: one below the surface, or degenerate,
// leaves N.
inline vec3 normal_mapped(const Scene& s, uint32_t prim, float u, float v, const SurfacePoint& sf, vec3 texel,
                          float scale) {
    const vec3 N = sf.ns;
    const float x = (2.f * texel.x - 1.f) * scale, y = (2.f * texel.y - 1.f) * scale, z = 2.f * texel.z - 1.f;
    if (x == 0.f && y == 0.f && z > 0.f) return N;  // a flat texel: N itself, bit for bit
    vec3 T(0.f), B(0.f);
    bool have = false;
    if (!s.tangent_indices.empty() && s.tangent_indices[prim].x != kNoIndex) {
        const uvec3 ti = s.tangent_indices[prim];
        const vec4 t0 = s.tangents[ti.x];
        const vec3 t = sf.b0 * vec3(t0) + u * vec3(s.tangents[ti.y]) + v * vec3(s.tangents[ti.z]);
        const vec3 to = t - N * glm::dot(N, t);
        const float l2 = glm::dot(to, to);
        if (l2 > 1e-12f && std::isfinite(l2)) {
            T = to / std::sqrt(l2);
            B = (t0.w < 0.f ? -1.f : 1.f) * glm::cross(N, T);
            have = true;
        }
    }
    if (!have && !s.uv_indices.empty() && s.uv_indices[prim].x != kNoIndex) {
        const uvec3 t = s.triangles[prim], ti = s.uv_indices[prim];
        const vec3 e1 = s.positions[t.y] - s.positions[t.x], e2 = s.positions[t.z] - s.positions[t.x];
        const vec2 d1 = s.uvs[ti.y] - s.uvs[ti.x], d2 = s.uvs[ti.z] - s.uvs[ti.x];
        const float det = d1.x * d2.y - d1.y * d2.x;
        if (std::fabs(det) > 1e-12f && std::isfinite(det)) {
            const vec3 dpdu = (d2.y * e1 - d1.y * e2) / det, dpdv = (d1.x * e2 - d2.x * e1) / det;
            const vec3 to = dpdu - N * glm::dot(N, dpdu);
            const float l2 = glm::dot(to, to);
            if (l2 > 1e-12f && std::isfinite(l2)) {
                T = to / std::sqrt(l2);
                B = glm::cross(N, T);
                if (glm::dot(B, dpdv) < 0.f) B = -B;  // uvs mirrored: the bitangent follows v
                have = true;
            }
        }
    }
    if (!have) {  // no usable uvs: any frame about N (the map's tilt then has no defined azimuth)
        const vec3 a = std::fabs(N.x) > 0.9f ? vec3(0.f, 1.f, 0.f) : vec3(1.f, 0.f, 0.f);
        T = glm::normalize(glm::cross(a, N));
        B = glm::cross(N, T);
    }
    const vec3 n = T * x + B * y + N * z;
    const float l2 = glm::dot(n, n);
    if (!(l2 > 1e-12f) || !std::isfinite(l2)) return N;
    const vec3 ns = n / std::sqrt(l2);
    return glm::dot(ns, sf.ng) > 0.f ? ns : N;  // tilted below the surface: the interpolated normal
}

// The shading normal n bent toward the geometric normal ng, in their plane, just enough that the mirror reflection of
// wo about it stays above the surface: its component along ng at least min(0.9 (wo . ng), 0.01) (Cycles'
// ensure_valid_reflection, with which Blender renders normal maps); n itself when it already is. Without the bend, a
// view grazing a normal tilted away from it lost the map at once (Veach's rule in shading_normals shades with ng
// where wo is behind the shading normal): flat, sharp-edged patches in the bumps at grazing angles, which made a
// normal map look stronger than in Blender. The result keeps wo in front of it (so that rule no longer applies). n
// and ng unit and on one side, wo unit on either side (the bend is made on wo's side).
inline vec3 valid_reflection_normal(vec3 ng, vec3 wo, vec3 n) {
    const float side = glm::dot(wo, ng) < 0.f ? -1.f : 1.f;
    const vec3 g = side * ng, m = side * n;
    const float iz = glm::dot(wo, g);
    const float threshold = std::min(0.9f * iz, 0.01f);
    if (glm::dot(2.f * glm::dot(m, wo) * m - wo, g) >= threshold) return n;
    // m = cos(phi0) g + sin(phi0) x. The reflection about cos(phi) g + sin(phi) x has the component
    // |w| cos(2 phi - alpha) along g, w = (wo . x, wo . g), alpha = atan2(wo . x, wo . g): at least the threshold for
    // 2 phi up to alpha + acos(threshold / |w|), where it is the threshold.
    const vec3 xo = m - glm::dot(m, g) * g;
    const float xl = glm::length(xo);
    if (!(xl > 1e-7f)) return ng;
    const vec3 x = xo / xl;
    const float phi0 = std::atan2(xl, glm::dot(m, g));
    const float ix = glm::dot(wo, x), len = std::sqrt(ix * ix + iz * iz);
    if (!(len > threshold)) return ng;
    const float psi = glm::clamp(std::atan2(ix, iz) + std::acos(threshold / len), 0.f, 2.f * phi0);
    return side * (std::cos(0.5f * psi) * g + std::sin(0.5f * psi) * x);
}

}  // namespace pv
