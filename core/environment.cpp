// core/environment.cpp: constant and equirectangular environments.
#include "core/environment.h"

#include "core/warp.h"

namespace pv {

EnvironmentSettings environment_settings(const Scene& scene) {
    EnvironmentSettings s;
    s.background = scene.background;
    s.rotation_deg = scene.environment_rotation_deg;
    s.strength = scene.environment_strength;
    s.sun_direction = scene.sun_direction;
    s.sun_angular_radius_deg = scene.sun_angular_radius_deg;
    s.sun_irradiance = scene.sun_irradiance;
    return s;
}

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
}  // namespace

bool environment_emits(const Scene& scene, const EnvironmentSettings& settings) {
    return sky_shines(scene, settings) || sun_shines(settings);
}

Environment::Environment(const Scene& scene, const EnvironmentSettings& settings) : m_strength(settings.strength) {
    m_rotation = glm::radians(settings.rotation_deg);
    m_sky_black = !sky_shines(scene, settings);
    if (has_map(scene)) {
        m_map = &scene.textures[scene.environment_map];
        const int w = m_map->width(), h = m_map->height();
        std::vector<float> f(size_t(w) * size_t(h));
        for (int y = 0; y < h; ++y) {
            // Texel rows are equal steps in theta; sin(theta) accounts for their shrinking solid angle.
            const float sin_theta = std::sin(kPi * (float(y) + 0.5f) / float(h));
            for (int x = 0; x < w; ++x) {
                const vec2 uv((float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h));
                f[size_t(y) * w + x] = luminance(vec3(m_map->lookup(vec2(uv.x, 1.f - uv.y)))) * sin_theta;
            }
        }
        m_dist = Distribution2D(f, w, h);
    } else {
        m_constant = settings.background * m_strength;
    }
    // The sun: irradiance E from a uniform disk of angular radius a is L pi sin^2(a), so L = E / (pi sin^2 a).
    const float radius = glm::radians(glm::clamp(settings.sun_angular_radius_deg, 0.01f, 45.f));
    if (sun_shines(settings)) {
        m_sun_dir = glm::normalize(settings.sun_direction);
        m_sun_cos = std::cos(radius);
        m_sun_radiance = settings.sun_irradiance / (kPi * sqr(std::sin(radius)));
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
    const float phi = uv.x * 2.f * kPi + m_rotation, theta = uv.y * kPi;
    const float s = std::sin(theta);
    return vec3(s * std::cos(phi), std::cos(theta), -s * std::sin(phi));
}

vec3 Environment::eval(vec3 dir) const {
    vec3 sun(0.f);
    if (m_p_sun > 0.f && glm::dot(dir, m_sun_dir) >= m_sun_cos) sun = m_sun_radiance;
    return sun + eval_sky(dir);
}

float Environment::pdf_sun(vec3 dir) const {
    // Uniform in the cone: solid angle 2 pi (1 - cos a).
    if (m_p_sun == 0.f || glm::dot(dir, m_sun_dir) < m_sun_cos) return 0.f;
    return 1.f / (2.f * kPi * (1.f - m_sun_cos));
}

vec3 Environment::eval_sky(vec3 dir) const {
    if (m_sky_black) return vec3(0.f);
    if (!m_map) return m_constant;
    const vec2 uv = direction_to_uv(dir);
    // Nearest texel: uv -> texel centre, so the radiance is constant over each sampled cell.
    const float x = (std::floor(uv.x * float(m_map->width())) + 0.5f) / float(m_map->width());
    const float y = (std::floor(uv.y * float(m_map->height())) + 0.5f) / float(m_map->height());
    return vec3(m_map->lookup(vec2(x, 1.f - y))) * m_strength;
}

std::optional<EnvironmentSample> Environment::sample(vec2 u) const {
    if (m_black) return std::nullopt;
    EnvironmentSample s;
    if (u.x < m_p_sun) {
        // The sun: uniform direction in its cone (u.x rescaled to [0, 1) for reuse).
        const float ux = glm::min(u.x / m_p_sun, kOneMinusEpsilon);
        const float cos_t = 1.f - ux * (1.f - m_sun_cos);
        const float sin_t = safe_sqrt(1.f - cos_t * cos_t);
        const float phi = 2.f * kPi * u.y;
        s.wi = m_sun_frame.to_world(vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t));
    } else if (!m_map) {
        const vec2 us((u.x - m_p_sun) / (1.f - m_p_sun), u.y);
        s.wi = square_to_uniform_sphere(vec2(glm::min(us.x, kOneMinusEpsilon), us.y));
    } else {
        const vec2 us(glm::min((u.x - m_p_sun) / (1.f - m_p_sun), kOneMinusEpsilon), u.y);
        float pdf_uv = 0.f;
        const vec2 uv = m_dist.sample(us, &pdf_uv);
        if (!(pdf_uv > 0.f) || !(std::sin(uv.y * kPi) > 0.f)) return std::nullopt;
        s.wi = uv_to_direction(uv);
    }
    s.pdf = pdf(s.wi);
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.le = eval(s.wi);
    return s;
}

float Environment::pdf(vec3 dir) const {
    if (m_black) return 0.f;
    return m_p_sun * pdf_sun(dir) + (1.f - m_p_sun) * pdf_sky(dir);
}

float Environment::pdf_sky(vec3 dir) const {
    if (m_sky_black) return 0.f;
    if (!m_map) return uniform_sphere_pdf();
    const vec2 uv = direction_to_uv(dir);
    const float sin_theta = std::sin(uv.y * kPi);
    if (!(sin_theta > 0.f)) return 0.f;
    // Jacobian of (u, v) -> direction: d omega = 2 pi^2 sin(theta) du dv.
    return m_dist.pdf(uv) / (2.f * kPi * kPi * sin_theta);
}

Texture make_default_sky() {
    const int w = 64, h = 512;  // constant in phi; fine in theta so the gradient shows no bands
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
