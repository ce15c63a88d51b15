// core/scene/environment.cpp: constant and equirectangular environments.
#include "core/scene/environment.h"

#include <algorithm>

#include "core/sampling/warp.h"

namespace pv {

namespace {
bool has_map(const Scene& scene) {
    return scene.environment_map != kNoIndex && scene.environment_map < scene.textures.size() &&
           scene.textures[scene.environment_map].width() > 0 && scene.textures[scene.environment_map].height() > 0;
}
bool sky_shines(const Scene& scene, const EnvironmentSettings& s) {
    return has_map(scene) ? s.strength > 0.f : !pv::is_black(s.background * s.strength);
}
bool sun_shines(const EnvironmentSettings& s) {
    const float len = glm::length(s.sun_direction);
    return !pv::is_black(s.sun_irradiance) && len > 0.f && std::isfinite(len);
}

// atan2(y, x) in [-pi, pi] from an odd degree-11 minimax polynomial for atan on [0, 1] (the coefficients often
// quoted after Abramowitz and Stegun 4.4.47's form). It only picks the candidate texel, which exact edge tests then
// correct, so its error just has to stay below the margin: max |error| 2.0e-6 rad measured against double atan2
// over 2e7 angles; kAtanMaxError leaves a factor 2 (tests/scene/test_environment_sampling.cpp checks it).
constexpr float kAtanMaxError = 4e-6f;
float atan2_approx(float y, float x) {
    const float ax = std::fabs(x), ay = std::fabs(y);
    const float hi = std::max(ax, ay), lo = std::min(ax, ay);
    const float t = hi > 0.f ? lo / hi : 0.f;
    const float z = t * t;
    float r = t * (0.99997726f +
                   z * (-0.33262347f + z * (0.19354346f + z * (-0.11643287f + z * (0.05265332f + z * -0.01172120f)))));
    if (ay > ax) r = 0.5f * kPi - r;
    if (x < 0.f) r = kPi - r;
    return std::copysign(r, y);
}

// Half-width, in cells, of the band around a cell edge where an approximate coordinate may sit on the wrong
// side: the angle error plus float rounding (relative 2^-23 of a coordinate up to n), times 4. Capped below half
// a cell so that an edge test only ever compares a direction with an edge less than half a cell away.
float edge_margin(int n, float span) {
    return std::min(0.45f, 1e-3f + 4.f * ((kAtanMaxError + 1e-6f) * float(n) / span + 1.2e-7f * float(n)));
}
}  // namespace

float environment_atan2_approx(float y, float x) { return atan2_approx(y, x); }
float environment_atan2_max_error() { return kAtanMaxError; }

bool environment_emits(const Scene& scene, const EnvironmentSettings& settings) {
    return sky_shines(scene, settings) || sun_shines(settings);
}

Environment::Environment(const Scene& scene, const EnvironmentSettings& settings) : m_strength(settings.strength) {
    m_rotation = glm::radians(settings.rotation_deg);
    m_rotation_cs = vec2(float(std::cos(double(m_rotation))), float(std::sin(double(m_rotation))));
    m_sky_black = !sky_shines(scene, settings);
    if (has_map(scene)) {
        m_map = &scene.textures[scene.environment_map];
        const int w = m_map->width(), h = m_map->height();
        std::vector<float> f(size_t(w) * size_t(h));
        m_radiance.resize(f.size());
        for (int y = 0; y < h; ++y) {
            // Texel rows are equal steps in theta; sin(theta) accounts for their shrinking solid angle. In double:
            // near theta = pi a float argument's rounding is a 1e-4 relative error of the sine.
            const float sin_theta = float(std::sin(M_PI * (double(y) + 0.5) / double(h)));
            for (int x = 0; x < w; ++x) {
                const vec2 uv((float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h));
                // At the texel centre the bilinear lookup is the texel itself.
                const vec3 le = vec3(m_map->lookup(vec2(uv.x, 1.f - uv.y)));
                f[size_t(y) * w + x] = luminance(le) * sin_theta;
                m_radiance[size_t(y) * w + x] = le * m_strength;
            }
        }
        m_dist = Distribution2D(f, w, h);
        // Texel edges as directions (in double, then rounded once) for the exact side tests of texel_index.
        m_col_edges.resize(size_t(w));
        for (int k = 0; k < w; ++k) {
            const double phi = 2.0 * M_PI * double(k) / double(w);
            m_col_edges[size_t(k)] = vec2(float(std::cos(phi)), float(std::sin(phi)));
        }
        m_row_edges.resize(size_t(h) + 1);
        for (int k = 0; k <= h; ++k) {
            const double theta = M_PI * double(k) / double(h);
            m_row_edges[size_t(k)] = vec2(float(std::sin(theta)), float(std::cos(theta)));
        }
        m_col_margin = edge_margin(w, 2.f * kPi);
        m_row_margin = edge_margin(h, kPi);
    } else {
        m_constant = settings.background * m_strength;
    }
    // The sun: irradiance E from a uniform disk of angular radius r is L pi sin^2(r), so L = E / (pi sin^2 r). Its
    // cone is kept as 1 - cos r = 2 sin^2(r/2) and sin^2 r, in double then rounded once: both keep full relative
    // precision for any radius, where cos r in float would be 1 below 0.02 degrees.
    const double radius =
        glm::radians(double(glm::clamp(settings.sun_angular_radius_deg, kSunRadiusMinDeg, kSunRadiusMaxDeg)));
    if (sun_shines(settings)) {
        const double sin_half = std::sin(0.5 * radius), sin_r = std::sin(radius);
        m_sun_dir = glm::normalize(settings.sun_direction);
        m_sun_one_minus_cos = float(2.0 * sin_half * sin_half);
        m_sun_sin2 = float(sin_r * sin_r);
        m_sun_radiance = vec3(dvec3(settings.sun_irradiance) / (M_PI * sin_r * sin_r));
        m_sun_pdf = float(1.0 / (4.0 * M_PI * sin_half * sin_half));  // uniform in a cone of 2 pi (1 - cos r)
        m_sun_frame = Frame(m_sun_dir);
        m_p_sun = m_sky_black ? 1.f : 0.5f;
    }
    m_black = m_sky_black && m_p_sun == 0.f;
}

vec2 Environment::direction_to_uv(vec3 d) const {
    // atan2 rather than acos(y): acos loses precision near the poles, where the pdf's 1/sin(theta) is large.
    const float theta = std::atan2(std::sqrt(d.x * d.x + d.z * d.z), d.y);
    float phi = std::atan2(-d.z, d.x) - m_rotation;
    phi -= 2.f * kPi * std::floor(phi * kInv2Pi);
    return vec2(glm::min(phi * kInv2Pi, kOneMinusEpsilon), glm::min(theta * kInvPi, kOneMinusEpsilon));
}

vec3 Environment::uv_to_direction(vec2 uv) const {
    // theta = pi v is half a turn of v; phi in map space is u turns, then rotated by m_rotation about +y.
    const vec2 cs_theta = cos_sin_turns(0.5f * uv.y), cs_map = cos_sin_turns(uv.x);
    const vec2 cs_phi(cs_map.x * m_rotation_cs.x - cs_map.y * m_rotation_cs.y,
                      cs_map.y * m_rotation_cs.x + cs_map.x * m_rotation_cs.y);
    return vec3(cs_theta.y * cs_phi.x, cs_theta.x, -cs_theta.y * cs_phi.y);
}

size_t Environment::texel_index(vec3 d, float* sin_theta) const {
    const int w = m_dist.width(), h = m_dist.height();
    const float rxz = std::sqrt(d.x * d.x + d.z * d.z);
    *sin_theta = rxz / std::sqrt(rxz * rxz + d.y * d.y);
    // Row: an approximate theta picks a candidate; near an edge the exact side test against that edge's
    // direction (sin theta_k, cos theta_k) decides. theta >= theta_k iff sin theta_k * y <= cos theta_k * rxz.
    auto past_row_edge = [&](int k) { return m_row_edges[size_t(k)].x * d.y <= m_row_edges[size_t(k)].y * rxz; };
    float a = atan2_approx(rxz, d.y) * (float(h) * kInvPi);
    a = a > 0.f ? a : 0.f;  // also maps NaN to 0
    int row = std::min(int(a), h - 1);
    float f = a - float(row);
    if (f < m_row_margin) {
        if (row > 0 && !past_row_edge(row)) --row;
    } else if (f > 1.f - m_row_margin) {
        if (row + 1 < h && past_row_edge(row + 1)) ++row;
    }
    // A map of one column (the default sky) has no column to find.
    if (w == 1) return size_t(row);
    // Column: the same in map space, (X, Y) = (cos, sin) of phi - rotation, wrapping at phi = 0; an edge
    // direction (cos phi_k, sin phi_k) is passed when the cross product with (X, Y) is >= 0.
    const float X = d.x * m_rotation_cs.x - d.z * m_rotation_cs.y;
    const float Y = -d.z * m_rotation_cs.x - d.x * m_rotation_cs.y;
    auto past_col_edge = [&](int k) { return m_col_edges[size_t(k)].x * Y >= m_col_edges[size_t(k)].y * X; };
    float t = atan2_approx(Y, X) * kInv2Pi;
    if (t < 0.f) t += 1.f;
    a = t * float(w);
    a = a > 0.f ? a : 0.f;
    int col = std::min(int(a), w - 1);
    f = a - float(col);
    if (f < m_col_margin) {
        if (!past_col_edge(col)) col = (col == 0 ? w : col) - 1;
    } else if (f > 1.f - m_col_margin) {
        const int next = col + 1 == w ? 0 : col + 1;
        if (past_col_edge(next)) col = next;
    }
    return size_t(row) * size_t(w) + size_t(col);
}

ivec2 Environment::direction_to_texel(vec3 dir) const {
    if (!m_map) return ivec2(0);
    float sin_theta = 0.f;
    const size_t i = texel_index(dir, &sin_theta);
    return ivec2(int(i % size_t(m_dist.width())), int(i / size_t(m_dist.width())));
}

vec3 Environment::eval(vec3 dir) const { return eval_sun(dir) + eval_sky(dir); }

bool Environment::in_sun(vec3 dir) const {
    // angle(dir, sun) <= r iff the angle is acute and sin^2 of it, |dir x sun|^2 / |dir|^2, is at most sin^2 r
    // (r <= 45 degrees). The cross product keeps a small angle's full relative precision, where the dot product
    // (its cosine) cannot resolve angles below float's 3.5e-4 rad = 0.02 degrees.
    const vec3 c = glm::cross(dir, m_sun_dir);
    return glm::dot(dir, m_sun_dir) > 0.f && glm::dot(c, c) <= m_sun_sin2 * glm::dot(dir, dir);
}

vec3 Environment::eval_sun(vec3 dir) const { return m_p_sun > 0.f && in_sun(dir) ? m_sun_radiance : vec3(0.f); }

float Environment::pdf_sun(vec3 dir) const { return m_p_sun > 0.f && in_sun(dir) ? m_sun_pdf : 0.f; }

vec3 Environment::eval_sky(vec3 dir) const {
    if (m_sky_black) return vec3(0.f);
    if (!m_map) return m_constant;
    float sin_theta = 0.f;
    return m_radiance[texel_index(dir, &sin_theta)];
}

std::optional<EnvironmentSample> Environment::sample(vec2 u) const {
    if (m_black) return std::nullopt;
    EnvironmentSample s;
    if (u.x < m_p_sun) {
        // The sun: a uniform direction in its cone, 1 - cos t = ux (1 - cos r), so sin^2 t = (1 - cos t)(1 + cos t)
        // keeps its precision at any radius (no rings of equal float cos t). u.x is rescaled to [0, 1) for reuse.
        // The direction is in the cone by construction, so the sun's radiance and pdf are taken as such: a
        // direction on the cone's edge may round outside in_sun(), which would otherwise lose it.
        const float ux = glm::min(u.x / m_p_sun, kOneMinusEpsilon);
        const float one_minus_cos = ux * m_sun_one_minus_cos;
        const float sin_t = std::sqrt(one_minus_cos * (2.f - one_minus_cos));
        const vec2 cs = cos_sin_turns(u.y);  // phi = 2 pi u.y
        s.wi = m_sun_frame.to_world(vec3(sin_t * cs.x, sin_t * cs.y, 1.f - one_minus_cos));
        s.pdf = m_p_sun * m_sun_pdf;
        s.le = m_sun_radiance;
        if (!m_sky_black) {
            if (m_map) {
                // One texel search serves both the sky's radiance and its pdf.
                float sin_theta = 0.f;
                const size_t texel = texel_index(s.wi, &sin_theta);
                s.pdf += (1.f - m_p_sun) * pdf_sky_texel(texel, sin_theta);
                s.le += m_radiance[texel];
            } else {
                s.pdf += (1.f - m_p_sun) * uniform_sphere_pdf();
                s.le += m_constant;
            }
        }
        if (!(s.pdf > 0.f)) return std::nullopt;
        return s;
    } else if (!m_map) {
        const vec2 us((u.x - m_p_sun) / (1.f - m_p_sun), u.y);
        s.wi = square_to_uniform_sphere(vec2(glm::min(us.x, kOneMinusEpsilon), us.y));
    } else {
        // The map: the sampled texel gives the radiance and the pdf directly (no search), so they match exactly.
        // Without a sun (m_p_sun = 0) the rescaling is the identity: skip its division (the same bits).
        const vec2 us(glm::min(m_p_sun == 0.f ? u.x : (u.x - m_p_sun) / (1.f - m_p_sun), kOneMinusEpsilon), u.y);
        float pdf_uv = 0.f;
        size_t texel = 0;
        const vec2 uv = m_dist.sample(us, &pdf_uv, &texel);
        s.wi = uv_to_direction(uv);
        const float sin_theta = std::sqrt(s.wi.x * s.wi.x + s.wi.z * s.wi.z);
        if (!(pdf_uv > 0.f) || !(sin_theta > 0.f)) return std::nullopt;
        if (m_p_sun == 0.f) {
            // No sun: the mixture below is 0 * 0 + 1 * pdf and 0 + radiance, these values exactly, without the call
            // to eval_sun (whose vec3 came back through memory, a store-forwarding stall).
            s.pdf = pdf_sky_texel(texel, sin_theta);
            s.le = m_radiance[texel];
            return s;
        }
        s.pdf = m_p_sun * pdf_sun(s.wi) + (1.f - m_p_sun) * pdf_sky_texel(texel, sin_theta);
        s.le = eval_sun(s.wi) + m_radiance[texel];
        return s;
    }
    s.pdf = pdf(s.wi);
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.le = eval(s.wi);
    return s;
}

float Environment::pdf(vec3 dir) const {
    if (m_black) return 0.f;
    return pdf_given_sky(dir, pdf_sky(dir));
}

float Environment::pdf_sky(vec3 dir) const {
    if (m_sky_black) return 0.f;
    if (!m_map) return uniform_sphere_pdf();
    float sin_theta = 0.f;
    const size_t texel = texel_index(dir, &sin_theta);
    return pdf_sky_texel(texel, sin_theta);
}

vec3 Environment::eval_and_pdf_sky(vec3 dir, float* sky_pdf) const {
    const vec3 sun = eval_sun(dir);
    if (m_sky_black) {
        *sky_pdf = 0.f;
        return sun;
    }
    if (!m_map) {
        *sky_pdf = uniform_sphere_pdf();
        return sun + m_constant;
    }
    float sin_theta = 0.f;
    const size_t texel = texel_index(dir, &sin_theta);
    *sky_pdf = pdf_sky_texel(texel, sin_theta);
    return sun + m_radiance[texel];
}

float Environment::pdf_sky_texel(size_t texel, float sin_theta) const {
    if (!(sin_theta > 0.f)) return 0.f;
    // Jacobian of (u, v) -> direction: d omega = 2 pi^2 sin(theta) du dv.
    return m_dist.pdf_cell(texel) / (2.f * kPi * kPi * sin_theta);
}

Texture make_default_sky() {
    // Constant in phi, so one column: the sampling tables (alias slots, pdfs, radiance) then take 12 KiB and stay in
    // cache, where 64 columns took 768 KiB that every light sample missed on in textured interiors
    // (docs/ray-speed.md). Fine in theta so the gradient shows no bands.
    const int w = 1, h = 512;
    std::vector<vec4> texels(size_t(w) * size_t(h));
    const vec3 zenith(0.35f, 0.55f, 1.0f), horizon(1.0f, 1.0f, 1.0f), ground(0.25f, 0.23f, 0.21f);
    for (int y = 0; y < h; ++y) {
        const float cos_theta = std::cos(kPi * (float(y) + 0.5f) / float(h));  // +1 at the zenith
        vec3 c;
        if (cos_theta >= 0.f) {
            c = glm::mix(horizon, zenith, std::pow(cos_theta, 0.5f));
        } else {
            c = glm::mix(horizon * 0.5f, ground, glm::min(1.f, -cos_theta * 4.f));
        }
        for (int x = 0; x < w; ++x) texels[size_t(y) * w + x] = vec4(c, 1.f);
    }
    return Texture(w, h, std::move(texels));
}

}  // namespace pv
