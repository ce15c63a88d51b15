// core/scene/medium.h: homogeneous participating media (issue 38, first step): their coefficients, the
// Henyey-Greenstein phase function (evaluated and sampled exactly) and free-flight distance sampling along a ray.
//
// Coefficients are per scene unit and per RGB channel. Distance sampling is spectral: one channel c is chosen with
// probability p_c proportional to the path throughput beta_c times the channel's single-scattering albedo (beta_c
// alone where the medium does not scatter; uniform when all are 0), a distance is drawn from that channel's
// exponential, and the sample is weighted by the one-sample MIS (balance heuristic) pdf averaged over the channels,
// sum_c p_c pdf_c(t), as pbrt-v4's VolPathIntegrator does for chromatic media (its r_u rescaling written as an
// explicit pdf average). Every channel's estimate stays unbiased whichever channel is drawn.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/base/math.h"

namespace pv {

// The largest |g| a scene file, --fog or the viewer gives (|g| -> 1 makes the phase function a delta).
constexpr float kMaxMediumG = 0.99f;

// A homogeneous medium: absorption and scattering coefficients per scene unit (RGB), and the Henyey-Greenstein
// asymmetry g in (-1, 1) (0: isotropic, > 0: forward scattering).
struct HomogeneousMedium {
    vec3 sigma_a{0.f};
    vec3 sigma_s{0.f};
    float g = 0.f;

    vec3 sigma_t() const { return sigma_a + sigma_s; }
    // A medium that does nothing to light (the default: no medium).
    bool empty() const { return is_black(sigma_a + sigma_s); }
    // Transmittance over distance d (Beer-Lambert).
    vec3 transmittance(float d) const { return glm::exp(-sigma_t() * d); }
    bool operator==(const HomogeneousMedium& o) const {
        return sigma_a == o.sigma_a && sigma_s == o.sigma_s && g == o.g;
    }
    // From albedo and density (sigma_t = density, sigma_s = albedo x density).
    static HomogeneousMedium from_albedo(vec3 albedo, float density, float g) {
        return HomogeneousMedium{(vec3(1.f) - albedo) * density, albedo * density, g};
    }
};

// Henyey-Greenstein phase function for the angle between the propagation direction before scattering (d, the ray's
// direction) and after (wi): cos_theta = dot(d, wi). Per steradian; integrates to 1 over the sphere.
inline float hg_phase(float cos_theta, float g) {
    const float denom = 1.f + g * g - 2.f * g * cos_theta;
    return (1.f - g * g) / (4.f * kPi * denom * std::sqrt(std::max(denom, 1e-12f)));
}

// Samples wi from the Henyey-Greenstein distribution around propagation direction d (unit): the exact inverse of its
// cosine's CDF, then a uniform azimuth. The pdf is hg_phase(dot(d, wi), g); the sample's weight p / pdf is 1.
inline vec3 sample_hg(vec3 d, float g, vec2 u) {
    float cos_theta;
    if (std::fabs(g) < 1e-3f) {
        cos_theta = 1.f - 2.f * u.x;
    } else {
        const float s = (1.f - g * g) / (1.f - g + 2.f * g * u.x);
        cos_theta = (1.f + g * g - s * s) / (2.f * g);
    }
    cos_theta = std::clamp(cos_theta, -1.f, 1.f);
    const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
    const float phi = 2.f * kPi * u.y;
    const Frame frame(d);
    return glm::normalize(frame.to_world(vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta)));
}

// The probabilities of choosing each channel for distance sampling (see the file comment), summing to 1.
inline vec3 channel_probabilities(const HomogeneousMedium& m, vec3 beta) {
    const vec3 st = m.sigma_t();
    vec3 w = glm::abs(beta);
    if (!is_black(m.sigma_s))
        for (int c = 0; c < 3; ++c) w[c] *= st[c] > 0.f ? m.sigma_s[c] / st[c] : 0.f;
    const float sum = w.x + w.y + w.z;
    if (!(sum > 0.f) || !std::isfinite(sum)) return vec3(1.f / 3.f);
    return w / sum;
}

// A free-flight distance along a ray segment of length tmax (may be infinite) through medium m.
struct DistanceSample {
    float t = 0.f;           // the scattering distance (scattered) or tmax
    bool scattered = false;  // a real scattering event before tmax
    // The factor the throughput takes: sigma_s T(t) / pdf(t) at a scattering event (the phase function's sample then
    // weighs 1), T(tmax) / P(t >= tmax) when the segment is passed.
    vec3 weight{1.f};
    float pdf = 1.f;  // the channel-averaged pdf (density at t, or the probability of passing)
};

// The channel-averaged density of drawing distance t (scattered) or the probability of passing tmax.
inline float distance_pdf(const HomogeneousMedium& m, vec3 probs, float t, bool scattered) {
    const vec3 st = m.sigma_t();
    const vec3 tr = glm::exp(-st * t);
    return scattered ? glm::dot(probs, st * tr) : glm::dot(probs, tr);
}

// Draws the distance: u_channel chooses the channel, u_dist the distance in it (inversion of its exponential).
inline DistanceSample sample_distance(const HomogeneousMedium& m, vec3 beta, float tmax, float u_channel,
                                      float u_dist) {
    const vec3 probs = channel_probabilities(m, beta);
    const int c = u_channel < probs.x ? 0 : (u_channel < probs.x + probs.y ? 1 : 2);
    const float st_c = m.sigma_t()[c];
    const float t =
        st_c > 0.f ? -std::log1p(-std::min(u_dist, 0x1.fffffep-1f)) / st_c : std::numeric_limits<float>::infinity();
    DistanceSample s;
    s.scattered = t < tmax;
    s.t = s.scattered ? t : tmax;
    if (std::isinf(s.t)) {
        // An unbounded segment passed: only channels without extinction could be drawn there, and they transmit 1.
        s.pdf = 1.f;
        s.weight = vec3(0.f);
        for (int k = 0; k < 3; ++k) s.weight[k] = m.sigma_t()[k] > 0.f ? 0.f : 1.f;
        float p_pass = 0.f;
        for (int k = 0; k < 3; ++k) p_pass += m.sigma_t()[k] > 0.f ? 0.f : probs[k];
        s.weight = p_pass > 0.f ? s.weight / p_pass : vec3(0.f);
        return s;
    }
    s.pdf = distance_pdf(m, probs, s.t, s.scattered);
    const vec3 tr = m.transmittance(s.t);
    s.weight = s.pdf > 0.f ? (s.scattered ? m.sigma_s * tr : tr) / s.pdf : vec3(0.f);
    return s;
}

// Equiangular sampling (Kulla and Fajardo 2012, "Importance Sampling Techniques for Path Tracing in Participating
// Media", sec. 4.1): a distance t in [0, tmax] along the ray o + t d (d unit, tmax may be infinite) toward a point c,
// with density proportional to 1 / |o + t d - c|^2, which cancels the point light's inverse-square falloff. With
// delta = dot(c - o, d) the foot of the perpendicular and h the distance from c to the line, t = delta + h tan(theta)
// for theta uniform in [theta_a, theta_b]; pdf(t) = h / ((theta_b - theta_a) (h^2 + (t - delta)^2)).
struct EquiangularSegment {
    float delta = 0.f, h = 0.f;
    float theta_a = 0.f, theta_b = 0.f;
    bool valid() const { return h > 0.f && theta_b > theta_a; }
};

// The segment's angles as seen from c; invalid (nothing to sample) when c lies on the ray's line.
inline EquiangularSegment equiangular_segment(vec3 o, vec3 d, vec3 c, float tmax) {
    EquiangularSegment e;
    e.delta = glm::dot(c - o, d);
    e.h = glm::length(c - (o + e.delta * d));
    if (!(e.h > 0.f) || !std::isfinite(e.h)) {
        e.h = 0.f;
        return e;
    }
    e.theta_a = std::atan2(-e.delta, e.h);
    e.theta_b = std::isinf(tmax) ? 0.5f * kPi : std::atan2(tmax - e.delta, e.h);
    return e;
}

inline float equiangular_pdf(const EquiangularSegment& e, float t) {
    const float x = t - e.delta;
    return e.h / ((e.theta_b - e.theta_a) * (e.h * e.h + x * x));
}

// The distance for u in [0, 1), clamped to [0, tmax] against rounding.
inline float sample_equiangular(const EquiangularSegment& e, float tmax, float u) {
    const float theta = e.theta_a + u * (e.theta_b - e.theta_a);
    return std::clamp(e.delta + e.h * std::tan(theta), 0.f, tmax);
}

}  // namespace pv
