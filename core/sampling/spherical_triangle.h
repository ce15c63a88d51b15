// core/sampling/spherical_triangle.h: uniform sampling of the solid angle a triangle subtends (Arvo 1995, in the form
// of pbrt-v4's SampleSphericalTriangle) and that solid angle itself (Van Oosterom and Strackee 1983).
#pragma once

#include <cmath>

#include "core/base/math.h"

namespace pv {

// The solid angle the triangle (p0, p1, p2) subtends at `ref`; 0 when ref lies in its plane or on a vertex.
inline float spherical_triangle_area(vec3 ref, vec3 p0, vec3 p1, vec3 p2) {
    const vec3 a = safe_normalize(p0 - ref), b = safe_normalize(p1 - ref), c = safe_normalize(p2 - ref);
    const float num = std::fabs(glm::dot(a, glm::cross(b, c)));
    const float den = 1.f + glm::dot(a, b) + glm::dot(a, c) + glm::dot(b, c);
    return std::fabs(2.f * std::atan2(num, den));
}

namespace detail {
// The component of v orthogonal to unit w, normalised (zero if v is parallel to w).
inline dvec3 orthonormal_part(dvec3 v, dvec3 w) {
    const dvec3 o = v - glm::dot(v, w) * w;
    const double l2 = glm::dot(o, o);
    return l2 > 0.0 ? o / std::sqrt(l2) : dvec3(0.0);
}
// Numerically stable for nearly parallel and nearly opposite unit vectors (pbrt-v4's AngleBetween).
inline double angle_between(dvec3 v1, dvec3 v2) {
    if (glm::dot(v1, v2) < 0.0) return M_PI - 2.0 * std::asin(glm::clamp(glm::length(v1 + v2) * 0.5, 0.0, 1.0));
    return 2.0 * std::asin(glm::clamp(glm::length(v2 - v1) * 0.5, 0.0, 1.0));
}
}  // namespace detail

// A direction uniformly distributed over the solid angle of triangle (p0, p1, p2) seen from `ref`, returned as
// the barycentrics (b1, b2) of the point it hits (p = (1-b1-b2) p0 + b1 p1 + b2 p2). False where the spherical
// triangle is degenerate (ref in the triangle's plane, or two corners in one direction). The density is
// 1 / spherical_triangle_area(ref, p0, p1, p2) per solid angle. In double: the algorithm loses the shape of thin
// spherical triangles (slivers, triangles seen nearly edge-on) in float.
inline bool sample_spherical_triangle(vec3 ref, vec3 p0, vec3 p1, vec3 p2, vec2 u, vec2& bary) {
    const dvec3 r(ref), v0 = dvec3(p0) - r, v1 = dvec3(p1) - r, v2 = dvec3(p2) - r;
    const double l0 = glm::length(v0), l1 = glm::length(v1), l2 = glm::length(v2);
    if (!(l0 > 0.0 && l1 > 0.0 && l2 > 0.0)) return false;
    const dvec3 a = v0 / l0, b = v1 / l1, c = v2 / l2;
    dvec3 n_ab = glm::cross(a, b), n_bc = glm::cross(b, c), n_ca = glm::cross(c, a);
    if (glm::dot(n_ab, n_ab) == 0.0 || glm::dot(n_bc, n_bc) == 0.0 || glm::dot(n_ca, n_ca) == 0.0) return false;
    n_ab = glm::normalize(n_ab);
    n_bc = glm::normalize(n_bc);
    n_ca = glm::normalize(n_ca);
    // The spherical triangle's angles at its corners; its area is alpha + beta + gamma - pi.
    const double alpha = detail::angle_between(n_ab, -n_ca);
    const double beta = detail::angle_between(n_bc, -n_ab);
    const double gamma = detail::angle_between(n_ca, -n_bc);
    const double area_pi = alpha + beta + gamma;
    if (!(area_pi > M_PI)) return false;
    // Sample a sub-triangle area A' uniformly in [0, A], then the corner c' on arc ac that gives that area.
    const double ap_pi = M_PI + double(u.x) * (area_pi - M_PI);
    const double cos_alpha = std::cos(alpha), sin_alpha = std::sin(alpha);
    const double sin_ap = std::sin(ap_pi), cos_ap = std::cos(ap_pi);
    const double sin_phi = sin_ap * cos_alpha - cos_ap * sin_alpha;
    const double cos_phi = cos_ap * cos_alpha + sin_ap * sin_alpha;
    const double k1 = cos_phi + cos_alpha;
    const double k2 = sin_phi - sin_alpha * glm::dot(a, b);
    double cos_bp = (k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha) / ((k2 * sin_phi + k1 * cos_phi) * sin_alpha);
    if (!std::isfinite(cos_bp)) return false;
    cos_bp = glm::clamp(cos_bp, -1.0, 1.0);
    const double sin_bp = std::sqrt(std::max(0.0, 1.0 - cos_bp * cos_bp));
    const dvec3 cp = cos_bp * a + sin_bp * detail::orthonormal_part(c, a);
    // Then a direction on arc b c' with the density that makes the whole uniform.
    const double cos_theta = 1.0 - double(u.y) * (1.0 - glm::dot(cp, b));
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    const dvec3 w = cos_theta * b + sin_theta * detail::orthonormal_part(cp, b);
    // Where w meets the triangle's plane (Moller-Trumbore with the ray ref + t w, relative to ref).
    const dvec3 e1 = v1 - v0, e2 = v2 - v0;
    const dvec3 s1 = glm::cross(w, e2);
    const double divisor = glm::dot(s1, e1);
    if (divisor == 0.0 || !std::isfinite(divisor)) return false;
    const dvec3 s = -v0;
    double b1 = glm::dot(s, s1) / divisor;
    double b2 = glm::dot(w, glm::cross(s, e1)) / divisor;
    if (!std::isfinite(b1) || !std::isfinite(b2)) return false;
    b1 = glm::clamp(b1, 0.0, 1.0);
    b2 = glm::clamp(b2, 0.0, 1.0);
    if (b1 + b2 > 1.0) {
        const double sum = b1 + b2;
        b1 /= sum;
        b2 /= sum;
    }
    bary = vec2(float(b1), float(b2));
    return true;
}

}  // namespace pv
