// core/sampling/warp.h: maps from the unit square to common domains, with their pdfs.
// Hemisphere warps are around +z; pdfs are per solid angle (per area for the triangle and disk).
#pragma once

#include "core/base/math.h"

namespace pv {

// (cos x, sin x) for |x| <= pi/4 (a little beyond is fine): Cephes' sinf/cosf minimax polynomials (Moshier,
// Cephes Math Library, sinf.c), degree 7 and 8. Max abs error vs double-precision sin/cos < 6e-8 (half an ulp
// of 1) over the range; tests/scene/test_bsdf_fast.cpp checks 1.2e-7. Replaces libm sincosf, whose range reduction
// the warps below never need.
inline vec2 cos_sin_reduced(float x) {
    const float z = x * x;
    const float s = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * x + x;
    const float c =
        ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z - 0.5f * z + 1.f;
    return vec2(c, s);
}

// (cos 2 pi u, sin 2 pi u) for 0 <= u < 2^21: the angle is measured in turns, so the reduction to
// [-pi/4, pi/4] around the nearest quarter turn is exact (4u and 4u - k are exact in float).
inline vec2 cos_sin_turns(float u) {
    const float q = 4.f * u;
    const int k = int(q + 0.5f);  // nearest quarter turn; truncation is floor since q >= 0
    const vec2 cs = cos_sin_reduced((q - float(k)) * (kPi / 2.f));
    // Rotate by k quarter turns: (c, s) -> (-s, c) -> (-c, -s) -> (s, -c).
    const vec2 r = (k & 1) ? vec2(cs.y, cs.x) : cs;
    return vec2((((k + 1) & 2) ? -r.x : r.x), ((k & 2) ? -r.y : r.y));
}

// Concentric map (Shirley and Chiu 1997) from [0,1)^2 to the unit disk; area-preserving up to a constant.
// In the wedge where |x| > |y|, theta = pi/4 * y/x; elsewhere theta = pi/2 - pi/4 * x/y, whose cos and sin are
// the sin and cos of pi/4 * x/y. So one division and one reduced-range sin/cos (pbrt-v4's SampleUniformDiskConcentric
// with the libm call replaced).
inline vec2 square_to_disk_concentric(vec2 u) {
    const vec2 o = 2.f * u - vec2(1.f);
    const bool x_major = std::fabs(o.x) > std::fabs(o.y);
    const float r = x_major ? o.x : o.y;
    if (r == 0.f) return vec2(0.f);  // o == 0: with |o.x| <= |o.y| = 0
    const vec2 cs = cos_sin_reduced((kPi / 4.f) * ((x_major ? o.y : o.x) / r));
    return r * (x_major ? cs : vec2(cs.y, cs.x));
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
    const vec2 cs = cos_sin_turns(u.y);  // phi = 2 pi u.y
    return vec3(r * cs.x, r * cs.y, z);
}
inline float uniform_sphere_pdf() { return 0.25f * kInvPi; }

inline vec3 square_to_uniform_hemisphere(vec2 u) {
    const float z = u.x;
    const float r = safe_sqrt(1.f - z * z);
    const vec2 cs = cos_sin_turns(u.y);  // phi = 2 pi u.y
    return vec3(r * cs.x, r * cs.y, z);
}
inline float uniform_hemisphere_pdf() { return kInv2Pi; }

// Uniform barycentrics (b1, b2) on a triangle (Heitz 2019 would avoid the sqrt; this is the classic form,
// b0 = 1 - b1 - b2). Density is uniform in area: pdf = 1/area.
inline vec2 square_to_triangle(vec2 u) {
    const float su = std::sqrt(u.x);
    return vec2(1.f - su, u.y * su);
}

}  // namespace pv
