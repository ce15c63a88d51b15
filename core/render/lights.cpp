// core/render/lights.cpp: the emitters' table and power-proportional selection (exact alias table); the pdf of a found
// emitter.
#include "core/render/lights.h"

#include <algorithm>

namespace pv {

LightSet::LightSet(const Scene& scene, const std::vector<Material>& materials, bool solid_angle)
    : m_solid_angle(solid_angle) {
    std::vector<double> power;
    std::vector<float> areas;
    // The mean RGB of each emissive texture (computed once per texture), which scales its emitters' power: exact up
    // to 2^22 texels, else from a 2048 x 2048 grid of lookups (any positive pmf is unbiased: when that grid finds
    // only black, the flat emission's power, so that no triangle that may emit loses its pmf).
    std::vector<std::pair<uint32_t, vec3>> texture_means;
    auto emissive_mean = [&](uint32_t tex) {
        for (const auto& [t, mean] : texture_means)
            if (t == tex) return mean;
        const Texture& texture = scene.textures[tex];
        dvec3 sum(0.0);
        size_t count = 0;
        const bool exact = size_t(texture.width()) * size_t(texture.height()) <= (size_t(1) << 22);
        if (exact) {
            const std::vector<vec4> texels = texture.texels();
            for (const vec4& x : texels) sum += dvec3(glm::max(vec3(x), vec3(0.f)));
            count = texels.size();
        } else {
            constexpr int kGrid = 2048;
            for (int y = 0; y < kGrid; ++y)
                for (int x = 0; x < kGrid; ++x)
                    sum +=
                        dvec3(glm::max(vec3(texture.lookup(vec2((x + 0.5f) / kGrid, (y + 0.5f) / kGrid))), vec3(0.f)));
            count = size_t(kGrid) * kGrid;
        }
        vec3 mean = count ? vec3(sum / double(count)) : vec3(0.f);
        if (!exact && is_black(mean)) mean = vec3(1.f);
        texture_means.emplace_back(tex, mean);
        return mean;
    };
    auto has_emissive_texture = [&](const Material& m) {
        return m.emissive_texture != kNoIndex && m.emissive_texture < scene.textures.size();
    };
    for (uint32_t i = 0; i < scene.triangles.size(); ++i) {
        const Material& m = materials[scene.material_ids[i]];
        if (!m.has_emission()) continue;
        const uvec3 t = scene.triangles[i];
        const vec3 p0 = scene.positions[t.x];
        const float area = 0.5f * glm::length(glm::cross(scene.positions[t.y] - p0, scene.positions[t.z] - p0));
        const vec3 le = has_emissive_texture(m) ? m.emission * emissive_mean(m.emissive_texture) : m.emission;
        const double w = double(luminance(le)) * area * (m.two_sided_emission ? 2.0 : 1.0);
        // Zero-area triangles, and emission whose power is not a positive finite number (an MTL "Ke 1e39" parses
        // as +inf), are never light-sampled: one infinite power would make every pmf 0 or NaN.
        if (!(area > 0.f) || !(w > 0.0) || !std::isfinite(w)) continue;
        m_tris.push_back(i);
        areas.push_back(area);
        power.push_back(w);
    }
    if (m_tris.empty()) return;
    double total = 0.0;
    for (double w : power) total += w;
    m_total_power = static_cast<float>(total * kPi);
    m_select = DiscreteDistribution(power);
    m_emitter_of.assign(scene.triangles.size(), kNoIndex);
    for (size_t k = 0; k < m_tris.size(); ++k) {
        const uint32_t tri = m_tris[k];
        const uvec3 t = scene.triangles[tri];
        const vec3 p0 = scene.positions[t.x], p1 = scene.positions[t.y], p2 = scene.positions[t.z];
        const Material& m = materials[scene.material_ids[tri]];
        const float pmf = m_select.pmf(k);
        m_emitter_of[tri] = uint32_t(k);
        const vec3 centre = (p0 + p1 + p2) / 3.f;
        const float r2 = std::max({glm::dot(p0 - centre, p0 - centre), glm::dot(p1 - centre, p1 - centre),
                                   glm::dot(p2 - centre, p2 - centre)});
        m_emitters.push_back({p0, p1, p2, safe_normalize(glm::cross(p1 - p0, p2 - p0)), m.emission, centre,
                              kSphericalNearRadii * kSphericalNearRadii * r2, pmf, pmf / areas[k], 1.f / areas[k],
                              float(power[k]), m.two_sided_emission});
        if (m.alpha_texture != kNoIndex && m.alpha_texture < scene.textures.size()) {
            // The alpha test's lookup (core/render/accel.cpp): the texture at the interpolated uv (0 without uvs).
            m_emitters.back().alpha = uint32_t(m_alpha.size());
            m_alpha.push_back({&scene.textures[m.alpha_texture], scene.uv_at(tri, 0.f, 0.f), scene.uv_at(tri, 1.f, 0.f),
                               scene.uv_at(tri, 0.f, 1.f)});
        }
        if (has_emissive_texture(m)) {
            // The texture's set (0 or 1) at the corners, untransformed: sample() interpolates, then transforms, as
            // Scene::texcoord does for a hit.
            UvTransform set;
            set.set = m.emissive_uv.set;
            m_emitters.back().emissive = uint32_t(m_emissive.size());
            m_emissive.push_back({&scene.textures[m.emissive_texture], m.emissive_uv,
                                  scene.texcoord(tri, 0.f, 0.f, set), scene.texcoord(tri, 1.f, 0.f, set),
                                  scene.texcoord(tri, 0.f, 1.f, set)});
        }
    }
}

void LightSet::set_groups(const Scene& scene, const std::vector<uint8_t>& material_group) {
    for (size_t k = 0; k < m_tris.size(); ++k) {
        const uint32_t m = scene.material_ids[m_tris[k]];
        m_emitters[k].group = m < material_group.size() ? material_group[m] : 0;
    }
}

void LightSet::set_sampler(LightSamplerKind kind) {
    m_use_tree = kind == LightSamplerKind::Tree && !m_emitters.empty();
    if (m_use_tree && m_tree.empty()) {
        std::vector<LightBounds> bounds;
        bounds.reserve(m_emitters.size());
        for (const Emitter& e : m_emitters)
            bounds.push_back(triangle_light_bounds(e.p0, e.p1, e.p2, e.power, e.two_sided));
        m_tree = LightTree(bounds);
    }
}

float LightSet::pdf(uint32_t tri, vec3 ref, vec3 ref_n, vec3 p, vec3 n) const {
    if (tri >= m_emitter_of.size() || m_emitter_of[tri] == kNoIndex) return 0.f;
    const uint32_t k = m_emitter_of[tri];
    const Emitter& e = m_emitters[k];
    const float pmf = m_use_tree ? m_tree.pmf(k, ref, ref_n) : e.pmf;
    if (pmf == 0.f) return 0.f;
    float omega = 0.f;
    if (spherical(e, ref, omega)) return pmf / omega;
    const float pdf_area = m_use_tree ? pmf * e.inv_area : e.pdf_area;
    const vec3 d = p - ref;
    const float d2 = glm::dot(d, d);
    const float cos_l = std::fabs(glm::dot(n, d)) / std::sqrt(d2);
    if (!(cos_l > 0.f)) return 0.f;
    return pdf_area * d2 / cos_l;
}

bool sample_punctual(const PunctualLight& l, vec3 ref, LightSample& out) {
    out.pdf = 1.f;
    out.p_error = vec3(0.f);
    if (l.type == PunctualLight::Type::Directional) {
        out.wi = -l.direction;
        out.dist = std::numeric_limits<float>::infinity();
        out.p = ref;
        out.n = l.direction;
        out.le = l.intensity;
        return !is_black(out.le);
    }
    const vec3 d = l.position - ref;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.f) || !std::isfinite(d2)) return false;
    out.dist = std::sqrt(d2);
    out.wi = d / out.dist;
    out.p = l.position;
    out.n = -out.wi;
    float scale = 1.f / d2;
    if (l.range > 0.f) {
        // KHR_lights_punctual's recommended falloff: clamp(1 - (d / range)^4, 0, 1)^2 / d^2.
        const float r = d2 / (l.range * l.range);
        scale *= sqr(glm::clamp(1.f - r * r, 0.f, 1.f));
    }
    if (l.type == PunctualLight::Type::Spot) {
        // The extension's smooth cone: t = clamp((cos - cos_outer) / max(1e-3, cos_inner - cos_outer), 0, 1), t^2.
        const float cos_outer = std::cos(l.outer_cone_rad), cos_inner = std::cos(l.inner_cone_rad);
        const float t =
            glm::clamp((glm::dot(l.direction, -out.wi) - cos_outer) / std::max(1e-3f, cos_inner - cos_outer), 0.f, 1.f);
        scale *= t * t;
    }
    out.le = l.intensity * scale;
    return !is_black(out.le) && is_finite(out.le);
}

}  // namespace pv
