// core/bsdf.cpp: evaluation, pdf and sampling of each lobe. See bsdf.h for the conventions.
#include "core/bsdf.h"

#include "core/warp.h"

#include <cfloat>

namespace pv {
namespace {

// Reflection lobes are two-sided: mirror both directions to the upper hemisphere of wo.
inline void to_upper(vec3& wo, vec3& wi) {
    if (wo.z < 0.f) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
}

inline vec3 reflect_z(vec3 w) { return vec3(-w.x, -w.y, w.z); }

// ---- Lambertian
vec3 eval_lobe(const Lambertian& b, vec3 wo, vec3 wi) {
    to_upper(wo, wi);
    return (wo.z > 0.f && wi.z > 0.f) ? b.albedo * kInvPi : vec3(0.f);
}
float pdf_lobe(const Lambertian&, vec3 wo, vec3 wi) {
    to_upper(wo, wi);
    return wo.z > 0.f ? cosine_hemisphere_pdf(wi.z) : 0.f;
}
std::optional<BsdfSample> sample_lobe(const Lambertian& b, vec3 wo, float, vec2 u) {
    if (wo.z == 0.f) return std::nullopt;
    vec3 wi = square_to_cosine_hemisphere(u);
    const float p = cosine_hemisphere_pdf(wi.z);
    if (p <= 0.f) return std::nullopt;  // wi.z == 0 at the disk's rim: a grazing, useless direction
    if (wo.z < 0.f) wi.z = -wi.z;
    return BsdfSample{b.albedo * kInvPi, wi, p, false};
}

// ---- Mirror
std::optional<BsdfSample> sample_lobe(const Mirror& b, vec3 wo, float, vec2) {
    if (!(std::fabs(wo.z) >= FLT_MIN)) return std::nullopt;  // zero or denormal: f = 1/|cos| would overflow
    const vec3 wi = reflect_z(wo);
    return BsdfSample{b.reflectance / std::fabs(wi.z), wi, 1.f, true};
}

// ---- Dielectric
std::optional<BsdfSample> sample_lobe(const Dielectric& b, vec3 wo, float u_lobe, vec2) {
    if (!(std::fabs(wo.z) >= FLT_MIN)) return std::nullopt;  // zero or denormal: f = 1/|cos| would overflow
    const float cos_o = wo.z;
    const float r = fresnel_dielectric(cos_o, b.eta);
    if (u_lobe < r) {
        const vec3 wi = reflect_z(wo);
        return BsdfSample{vec3(r / std::fabs(wi.z)), wi, r, true};
    }
    // Refraction (Snell): relative eta seen from wo's side.
    const bool entering = cos_o > 0.f;
    const float eta = entering ? b.eta : 1.f / b.eta;
    const float abs_cos_o = std::fabs(cos_o);
    const float sin2_t = (1.f - abs_cos_o * abs_cos_o) / (eta * eta);
    if (sin2_t >= 1.f) return std::nullopt;  // total internal reflection: r == 1, unreachable
    const float cos_t = std::sqrt(1.f - sin2_t);
    vec3 wi = -wo / eta;
    wi.z = entering ? -cos_t : cos_t;
    wi = glm::normalize(wi);
    const float t = 1.f - r;
    // Radiance is compressed by 1/eta^2 when entering a denser medium (Veach 1997, sec. 5.2).
    return BsdfSample{vec3(t / (eta * eta) / std::fabs(wi.z)), wi, t, true, eta};
}

// ---- Glossy: diffuse + GGX specular
float spec_prob(const Glossy& b) {
    const float s = luminance(b.specular), d = luminance(b.diffuse);
    return (s + d) > 0.f ? s / (s + d) : 1.f;
}
vec3 eval_lobe(const Glossy& b, vec3 wo, vec3 wi) {
    to_upper(wo, wi);
    if (wo.z <= 0.f || wi.z <= 0.f) return vec3(0.f);
    vec3 h = wo + wi;
    const float len2 = glm::dot(h, h);
    if (len2 == 0.f) return b.diffuse * kInvPi;
    h /= std::sqrt(len2);
    // G1(w) / cos(w) per direction: finite (-> 2 / alpha) at grazing, where 4 cos_o cos_i can underflow to 0.
    const float spec =
        0.25f * ggx_d(h, b.alpha) * (ggx_g1(wo, b.alpha) / wo.z) * (ggx_g1(wi, b.alpha) / wi.z);
    return b.diffuse * kInvPi + b.specular * spec;
}
float pdf_lobe(const Glossy& b, vec3 wo, vec3 wi) {
    to_upper(wo, wi);
    if (wo.z <= 0.f || wi.z <= 0.f) return 0.f;
    const float ps = spec_prob(b);
    vec3 h = wo + wi;
    const float len2 = glm::dot(h, h);
    float p_spec = 0.f;
    if (len2 > 0.f) {
        h /= std::sqrt(len2);
        // VNDF: pdf(h) = G1(wo) max(0, wo.h) D(h) / wo.z; Jacobian dh/dwi = 1 / (4 wo.h).
        p_spec = ggx_g1(wo, b.alpha) * ggx_d(h, b.alpha) / (4.f * wo.z);
    }
    return ps * p_spec + (1.f - ps) * cosine_hemisphere_pdf(wi.z);
}
std::optional<BsdfSample> sample_lobe(const Glossy& b, vec3 wo, float u_lobe, vec2 u) {
    if (wo.z == 0.f) return std::nullopt;
    const bool flip = wo.z < 0.f;
    const vec3 wo_up = flip ? vec3(wo.x, wo.y, -wo.z) : wo;
    vec3 wi;
    if (u_lobe < spec_prob(b)) {
        const vec3 h = ggx_sample_visible_normal(wo_up, b.alpha, u);
        wi = 2.f * glm::dot(wo_up, h) * h - wo_up;
        if (wi.z <= 0.f) return std::nullopt;
    } else {
        wi = square_to_cosine_hemisphere(u);
        if (wi.z <= 0.f) return std::nullopt;
    }
    const float p = pdf_lobe(b, wo_up, wi);
    if (!(p > 0.f)) return std::nullopt;
    const vec3 f = eval_lobe(b, wo_up, wi);
    if (flip) wi.z = -wi.z;
    return BsdfSample{f, wi, p, false};
}

template <class T>
vec3 eval_lobe(const T&, vec3, vec3) { return vec3(0.f); }
template <class T>
float pdf_lobe(const T&, vec3, vec3) { return 0.f; }

}  // namespace

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
    const vec3 t1 = lensq > 0.f ? vec3(-vh.y, vh.x, 0.f) / std::sqrt(lensq) : vec3(1.f, 0.f, 0.f);
    const vec3 t2 = glm::cross(vh, t1);
    const float r = std::sqrt(u.x);
    const float phi = 2.f * kPi * u.y;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
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

float alpha_from_ns(float ns) { return glm::clamp(std::sqrt(2.f / (glm::max(ns, 0.f) + 2.f)), kMinAlpha, 1.f); }

vec3 eval(const Bsdf& bsdf, vec3 wo, vec3 wi) {
    return std::visit([&](const auto& b) { return eval_lobe(b, wo, wi); }, bsdf);
}
float pdf(const Bsdf& bsdf, vec3 wo, vec3 wi) {
    return std::visit([&](const auto& b) { return pdf_lobe(b, wo, wi); }, bsdf);
}
std::optional<BsdfSample> sample(const Bsdf& bsdf, vec3 wo, float u_lobe, vec2 u) {
    return std::visit([&](const auto& b) { return sample_lobe(b, wo, u_lobe, u); }, bsdf);
}
bool is_delta(const Bsdf& bsdf) {
    return std::holds_alternative<Mirror>(bsdf) || std::holds_alternative<Dielectric>(bsdf);
}
void set_base_color(Bsdf& bsdf, vec3 color) {
    if (auto* l = std::get_if<Lambertian>(&bsdf)) l->albedo = glm::clamp(color, vec3(0.f), vec3(1.f));
    if (auto* g = std::get_if<Glossy>(&bsdf)) g->diffuse = glm::clamp(color, vec3(0.f), vec3(1.f) - g->specular);
}

const char* bsdf_type_name(const Bsdf& bsdf) {
    static const char* names[] = {"diffuse", "mirror", "glass", "glossy"};
    return names[bsdf.index()];
}

}  // namespace pv
