// core/scene/microfacet.cpp: GGX and Fresnel (see microfacet.h).
#include "core/scene/microfacet.h"

#include <cmath>

namespace pv {

float ggx_d(vec3 h, float alpha) {
    if (h.z <= 0.f) return 0.f;
    const float a2 = alpha * alpha;
    const float c2 = h.z * h.z;
    const float d = c2 * (a2 - 1.f) + 1.f;
    return a2 / (kPi * d * d);
}

float ggx_g1(vec3 w, float alpha) {
    // Smith G1 for GGX: 2 / (1 + sqrt(1 + alpha^2 tan^2)), written without tan to stay finite at grazing.
    const float c2 = w.z * w.z;
    if (c2 <= 0.f) return 0.f;
    const float s2 = glm::max(0.f, 1.f - c2);
    return 2.f / (1.f + std::sqrt(1.f + alpha * alpha * s2 / c2));
}

vec3 ggx_sample_visible_normal(vec3 wo, float alpha, vec2 u) {
    // Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)), listing 1.
    const vec3 vh = glm::normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));
    const float lensq = vh.x * vh.x + vh.y * vh.y;
    const vec3 t1 = lensq > 0.f ? vec3(-vh.y, vh.x, 0.f) * (1.f / std::sqrt(lensq)) : vec3(1.f, 0.f, 0.f);
    const vec3 t2 = glm::cross(vh, t1);
    const float r = std::sqrt(u.x);
    const vec2 cs = cos_sin_turns(u.y);  // phi = 2 pi u.y
    const float p1 = r * cs.x;
    float p2 = r * cs.y;
    const float s = 0.5f * (1.f + vh.z);
    p2 = (1.f - s) * safe_sqrt(1.f - p1 * p1) + s * p2;
    const vec3 nh = p1 * t1 + p2 * t2 + safe_sqrt(1.f - p1 * p1 - p2 * p2) * vh;
    return glm::normalize(vec3(alpha * nh.x, alpha * nh.y, glm::max(1e-6f, nh.z)));
}

float fresnel_dielectric(float cos_i, float eta) {
    cos_i = glm::clamp(cos_i, -1.f, 1.f);
    if (cos_i < 0.f) {
        eta = 1.f / eta;
        cos_i = -cos_i;
    }
    const float sin2_t = (1.f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.f) return 1.f;
    const float cos_t = safe_sqrt(1.f - sin2_t);
    const float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}

}  // namespace pv
