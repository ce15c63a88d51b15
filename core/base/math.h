// core/base/math.h: vector types (GLM), constants and small numeric helpers shared by the renderer.
// Colours are linear RGB in vec3. Directions are unit vectors unless a name says otherwise.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>

namespace pv {

using glm::dvec3;
using glm::ivec2;
using glm::uvec2;
using glm::uvec3;
using glm::vec2;
using glm::vec3;
using glm::vec4;

constexpr uint32_t kNoIndex = 0xffffffffu;  // "no element" for 32-bit indices
constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInv2Pi = 0.15915494309189533577f;
// The largest float below 1 (pbrt's OneMinusEpsilon): uniform samples live in [0, 1).
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

inline float max_component(vec3 v) { return glm::max(v.x, glm::max(v.y, v.z)); }
inline float luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline bool is_black(vec3 c) { return c.x == 0.f && c.y == 0.f && c.z == 0.f; }
inline bool is_finite(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline float safe_sqrt(float x) { return std::sqrt(glm::max(x, 0.f)); }
inline float sqr(float x) { return x * x; }

// The rare path of safe_normalize, kept out of line so that the common one inlines.
[[gnu::cold, gnu::noinline]] inline vec3 normalize_rescaled(vec3 v) {
    if (!is_finite(v)) return vec3(0.f);
    const float m = max_component(glm::abs(v));
    if (!(m > 0.f)) return vec3(0.f);
    // A division, not v * (1 / m): for m near FLT_MAX, 1 / m is subnormal and the renderer's threads flush it to 0.
    const vec3 s = v / m;
    return s / std::sqrt(glm::dot(s, s));
}

// v / |v|, also where |v|^2 overflows or underflows float (huge or tiny triangles): v is then rescaled by its
// largest component first. 0 for a zero or non-finite v.
inline vec3 safe_normalize(vec3 v) {
    const float l2 = glm::dot(v, v);
    if (std::isnormal(l2)) return v * (1.f / std::sqrt(l2));
    return normalize_rescaled(v);
}

// An orthonormal frame around n (+z = n). Construction after Duff et al. 2017,
// "Building an Orthonormal Basis, Revisited" (JCGT 6(1)): branchless and exact for n = -z.
struct Frame {
    vec3 t{1, 0, 0}, b{0, 1, 0}, n{0, 0, 1};

    Frame() = default;
    explicit Frame(vec3 normal) : n(normal) {
        const float sign = std::copysign(1.f, n.z);
        const float a = -1.f / (sign + n.z);
        const float bb = n.x * n.y * a;
        t = vec3(1.f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
        b = vec3(bb, sign + n.y * n.y * a, -n.y);
    }
    vec3 to_local(vec3 v) const { return vec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)); }
    vec3 to_world(vec3 v) const { return v.x * t + v.y * b + v.z * n; }
};

// Conservative bound on the rounding error of a point p = b0 p0 + b1 p1 + b2 p2 computed in float from a
// triangle's vertices and barycentrics: gamma(7) (|b0 p0| + |b1 p1| + |b2 p2|), gamma(n) = n eps / (1 - n eps)
// (pbrt-v4, Triangle::InteractionFromIntersection).
inline vec3 barycentric_error(vec3 p0, vec3 p1, vec3 p2, float b0, float b1, float b2) {
    constexpr float kGamma7 = 7.f * 0x1p-24f / (1.f - 7.f * 0x1p-24f);
    return kGamma7 * (glm::abs(b0 * p0) + glm::abs(b1 * p1) + glm::abs(b2 * p2));
}

// The next float above / below v (pbrt-v4's NextFloatUp/Down), inline: no libm call. +inf stays +inf (-inf
// stays -inf); -0 and +0 step to the smallest positive (negative) denormal.
inline float next_float_up(float v) {
    if (std::isinf(v) && v > 0.f) return v;
    if (v == -0.f) v = 0.f;
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    bits = v >= 0.f ? bits + 1 : bits - 1;
    std::memcpy(&v, &bits, 4);
    return v;
}
inline float next_float_down(float v) {
    if (std::isinf(v) && v < 0.f) return v;
    if (v == 0.f) v = -0.f;
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    bits = v > 0.f ? bits - 1 : bits + 1;
    std::memcpy(&v, &bits, 4);
    return v;
}

// Offsets a ray origin p off a surface with geometric normal n (pointing to the side the ray leaves).
// Method of Waechter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
// Ray Tracing Gems ch. 6: move p by a fixed number of float ULPs along n (scale-invariant). Spawn with tmin = 0.
// p_error (from barycentric_error) makes it robust where p's own rounding error exceeds those ULPs (a triangle
// whose vertices are many orders of magnitude larger than p): p then moves at least dot(|n|, p_error) along n,
// rounded away from p (pbrt-v4, OffsetRayOrigin).
[[gnu::always_inline]] inline vec3 offset_ray_origin(vec3 p, vec3 n, vec3 p_error = vec3(0.f)) {
    // Waechter and Binder move coordinates below 1/32 by a fixed 1/65536 instead of ULPs, since ULPs near zero are
    // far smaller than the rounding error of a hit point computed from larger vertices. Here that error is bounded
    // by p_error, so the fixed distance (a leak in millimetre-sized scenes: 1/65536 is 1.5% of 1e-3) is only used
    // where a ULP step would leave the normal floats that FTZ/DAZ tracing keeps (|p| < 1e-30).
    constexpr float kTiny = 1e-30f;
    constexpr float kIntScale = 256.f;
    const float d = glm::dot(glm::abs(n), p_error);
    vec3 out;
    for (int i = 0; i < 3; ++i) {
        const int of = static_cast<int>(kIntScale * n[i]);
        int32_t bits;
        std::memcpy(&bits, &p[i], 4);
        bits += (p[i] < 0) ? -of : of;
        float pi;
        std::memcpy(&pi, &bits, 4);
        float o = std::fabs(p[i]) < kTiny ? p[i] + kTiny * n[i] : pi;
        if (d > 0.f) {
            if (n[i] > 0.f) o = glm::max(o, next_float_up(p[i] + d * n[i]));
            if (n[i] < 0.f) o = glm::min(o, next_float_down(p[i] + d * n[i]));
        }
        out[i] = o;
    }
    return out;
}

}  // namespace pv
