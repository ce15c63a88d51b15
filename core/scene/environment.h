// core/scene/environment.h: light from infinitely far away: a sky (a constant radiance, or an equirectangular map)
// plus an optional sun disk. Sampling picks the sun or the sky (one half each when both shine) and pdf() is the
// mixture of the two, so MIS sees one light.
#pragma once

#include <optional>
#include <vector>

#include "core/sampling/distribution.h"
#include "core/scene/scene.h"

namespace pv {

struct EnvironmentSample {
    vec3 wi{0.f};  // world direction toward the environment
    vec3 le{0.f};  // radiance arriving from it
    float pdf = 0.f;
};

// The sun's angular radius in degrees that scene files and --sun-radius accept; the sky clamps it to this range.
constexpr float kSunRadiusMinDeg = 0.01f, kSunRadiusMaxDeg = 45.f;

// True if the environment with these settings gives any light; cheap (no sampling tables are built).
bool environment_emits(const Scene& scene, const EnvironmentSettings& settings);

// The sky is a constant radiance, or an equirectangular map (latitude-longitude, +y up) importance-sampled by a
// piecewise-constant distribution over its texels weighted by luminance * sin(theta). The map is looked up per texel
// (no filtering) so the sampling pdf is exactly proportional to the radiance it returns: eval() and pdf() find a
// direction's texel with the same search (an approximate angle, then exact tests against the texel's edge
// directions), and sample() returns the radiance and pdf of the texel it sampled. Directions: theta = acos(y);
// phi = atan2(-z, x) + rotation, so the map's centre column (u = 0.5) faces -x. pdfs are per solid angle.
class Environment {
public:
    Environment() = default;
    // From the scene: its environment map if any, else its constant background; both times its strength.
    explicit Environment(const Scene& scene) : Environment(scene, scene.environment) {}
    // The scene's map (if any) with other parameters.
    Environment(const Scene& scene, const EnvironmentSettings& settings);

    bool is_black() const { return m_black; }
    vec3 eval(vec3 dir) const;
    std::optional<EnvironmentSample> sample(vec2 u) const;
    float pdf(vec3 dir) const;
    // The parts of pdf(): pdf(d) = sun_probability() pdf_sun(d) + (1 - sun_probability()) pdf_sky(d) (light portals
    // replace part of the sky's sampling only, see traceable_scene.h). sample() with u.x < sun_probability() samples
    // the sun, otherwise the sky.
    float sun_probability() const { return m_p_sun; }
    float pdf_sun(vec3 dir) const;
    float pdf_sky(vec3 dir) const;
    // pdf(dir) given pdf_sky(dir) (a caller that has it from eval_and_pdf_sky's texel search).
    float pdf_given_sky(vec3 dir, float sky_pdf) const { return m_p_sun * pdf_sun(dir) + (1.f - m_p_sun) * sky_pdf; }
    vec3 eval_sky(vec3 dir) const;  // the sky's radiance alone (no sun)
    vec3 eval_sun(vec3 dir) const;  // the sun's alone (no sky)
    // eval(dir), and pdf_sky(dir) in *sky_pdf, with one texel search.
    vec3 eval_and_pdf_sky(vec3 dir, float* sky_pdf) const;

    // The equirectangular parameterisation (exposed for tests): uv in [0,1)^2, v = 0 at the zenith.
    // direction_to_uv is the libm reference; eval/pdf use direction_to_texel, which agrees with
    // floor(direction_to_uv(dir) * size) except within float rounding of a texel edge.
    vec2 direction_to_uv(vec3 dir) const;
    vec3 uv_to_direction(vec2 uv) const;
    // The map texel (column, row from the zenith) that eval() and pdf() use for dir (any length, not 0); (0, 0)
    // without a map.
    ivec2 direction_to_texel(vec3 dir) const;

private:
    bool m_black = true;
    bool m_sky_black = true;
    vec3 m_constant{0.f};
    // Sun: unit direction; its angular radius r as 1 - cos r = 2 sin^2(r/2) and sin^2 r (float's cos r is 1 for
    // r below 0.02 degrees, and 1 - cos r loses all but a few bits near the real sun's 0.27); radiance, and the
    // probability of sampling it.
    vec3 m_sun_dir{0.f, 1.f, 0.f};
    float m_sun_one_minus_cos = 0.f;
    float m_sun_sin2 = 0.f;
    float m_sun_pdf = 0.f;  // 1 / (2 pi (1 - cos r)), uniform in the cone
    vec3 m_sun_radiance{0.f};
    float m_p_sun = 0.f;
    Frame m_sun_frame;

    bool in_sun(vec3 dir) const;  // dir (any length, not 0) within the sun's angular radius
    float pdf_sky_texel(size_t texel, float sin_theta) const;  // map pdf toward a direction in that texel
    // Texel index row * width + column of dir, and sin(theta) of dir (0 at the poles).
    size_t texel_index(vec3 dir, float* sin_theta) const;
    const Texture* m_map = nullptr;
    float m_strength = 1.f;
    float m_rotation = 0.f;        // radians
    vec2 m_rotation_cs{1.f, 0.f};  // cos, sin of m_rotation
    Distribution2D m_dist;
    std::vector<vec3> m_radiance;                  // per texel, times the strength: what eval_sky returns
    std::vector<vec2> m_col_edges;                 // (cos, sin) of phi_k = 2 pi k / width, map space, k < width
    std::vector<vec2> m_row_edges;                 // (sin, cos) of theta_k = pi k / height, k <= height
    float m_col_margin = 0.f, m_row_margin = 0.f;  // approximate-angle error bound, in texels
};

// The approximate atan2 (radians, in [-pi, pi]) that picks a direction's candidate texel, and the bound on its
// absolute error that the texel search assumes (exposed for tests).
float environment_atan2_approx(float y, float x);
float environment_atan2_max_error();

// A plain sky as an equirectangular map: bluish zenith, white horizon, a darker ground. Radiance about 1.
Texture make_default_sky();

}  // namespace pv
