// core/warp.h: maps from the unit square to common domains, with their pdfs.
// Hemisphere warps are around +z; pdfs are per solid angle (per area for the triangle and disk).
#pragma once

#include "core/math.h"

namespace pv {

// Concentric map (Shirley and Chiu 1997) from [0,1)^2 to the unit disk; area-preserving up to a constant.
inline vec2 square_to_disk_concentric(vec2 u) {
    const vec2 o = 2.f * u - vec2(1.f);
    if (o.x == 0.f && o.y == 0.f) return vec2(0.f);
    float r, theta;
    if (std::fabs(o.x) > std::fabs(o.y)) {
        r = o.x;
        theta = (kPi / 4.f) * (o.y / o.x);
    } else {
        r = o.y;
        theta = (kPi / 2.f) - (kPi / 4.f) * (o.x / o.y);
    }
    return r * vec2(std::cos(theta), std::sin(theta));
}

// Malley's method: cosine-weighted hemisphere, pdf = cos(theta)/pi.
inline vec3 square_to_cosine_hemisphere(vec2 u) {
    const vec2 d = square_to_disk_concentric(u);
    const float z = safe_sqrt(1.f - d.x * d.x - d.y * d.y);
    return vec3(d.x, d.y, z);
}
inline float cosine_hemisphere_pdf(float cos_theta) { return cos_theta > 0.f ? cos_theta * kInvPi : 0.f; }

inline vec3 square_to_uniform_sphere(vec2 u) {
    const float z = 1.f - 2.f * u.x;
    const float r = safe_sqrt(1.f - z * z);
    const float phi = 2.f * kPi * u.y;
    return vec3(r * std::cos(phi), r * std::sin(phi), z);
}
inline float uniform_sphere_pdf() { return 0.25f * kInvPi; }

inline vec3 square_to_uniform_hemisphere(vec2 u) {
    const float z = u.x;
    const float r = safe_sqrt(1.f - z * z);
    const float phi = 2.f * kPi * u.y;
    return vec3(r * std::cos(phi), r * std::sin(phi), z);
}
inline float uniform_hemisphere_pdf() { return kInv2Pi; }

// Uniform barycentrics (b1, b2) on a triangle (Heitz 2019 would avoid the sqrt; this is the classic form,
// b0 = 1 - b1 - b2). Density is uniform in area: pdf = 1/area.
inline vec2 square_to_triangle(vec2 u) {
    const float su = std::sqrt(u.x);
    return vec2(1.f - su, u.y * su);
}

}  // namespace pv
