// core/scene/bsdf.cpp: evaluation, pdf and sampling of each lobe. See bsdf.h for the conventions.
#include "core/scene/bsdf.h"

#include <cfloat>

#include "core/sampling/warp.h"

namespace pv {
namespace {

inline vec3 reflect_z(vec3 w) { return vec3(-w.x, -w.y, w.z); }

// ---- Mirror
std::optional<BsdfSample> sample_lobe(const Mirror& b, vec3 wo) {
    if (!(std::fabs(wo.z) >= FLT_MIN)) return std::nullopt;  // zero or denormal: f = 1/|cos| would overflow
    const vec3 wi = reflect_z(wo);
    return BsdfSample{b.reflectance / std::fabs(wi.z), wi, 1.f, true};
}

// ---- Dielectric
std::optional<BsdfSample> sample_lobe(const Dielectric& b, vec3 wo, float u_lobe) {
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
    const float inv_eta2 = 1.f / (eta * eta);
    const float abs_cos_o = std::fabs(cos_o);
    const float sin2_t = (1.f - abs_cos_o * abs_cos_o) * inv_eta2;
    if (sin2_t >= 1.f) return std::nullopt;  // total internal reflection: r == 1, unreachable
    const float cos_t = std::sqrt(1.f - sin2_t);
    // -wo/eta with z replaced, then normalised: the scale 1/eta cancels in the normalisation except on z.
    const vec3 wi = glm::normalize(vec3(-wo.x, -wo.y, (entering ? -cos_t : cos_t) * eta));
    const float t = 1.f - r;
    // Radiance is compressed by 1/eta^2 when entering a denser medium (Veach 1997, sec. 5.2).
    return BsdfSample{vec3(t * inv_eta2 / std::fabs(wi.z)), wi, t, true, eta};
}

// ---- Glossy: diffuse + GGX specular
float spec_prob(const Glossy& b) {
    const float s = luminance(b.specular), d = luminance(b.diffuse);
    return (s + d) > 0.f ? s / (s + d) : 1.f;
}

// cos(w) / G1(w) * 2 for GGX, = cos + sqrt(cos^2 + alpha^2 sin^2): Smith's G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2))
// (Heitz 2014, eq. 86) multiplied through by cos, so it stays finite at grazing and costs no division.
// Zero where cos^2 underflows, as ggx_g1() is.
inline float ggx_cos_over_g1_x2(float c, float a2) {
    const float c2 = c * c;
    if (c2 <= 0.f) return 0.f;
    return c + std::sqrt(c2 + a2 * glm::max(0.f, 1.f - c2));
}

// pi * D(h)^-1 * alpha^2 for h = normalize(wo + wi), i.e. pi (sin^2 h + alpha^2 cos^2 h)^2, the GGX denominator
// 1 + cos^2 (alpha^2 - 1) written without its cancellation near h = z; h is never normalised. 0 if wo = -wi.
// Precondition: wo.z > 0, wi.z > 0 (so h.z > 0, where ggx_d() is nonzero).
inline float ggx_pi_d2(vec3 wo, vec3 wi, float a2) {
    const vec3 h = wo + wi;
    const float sin2 = h.x * h.x + h.y * h.y, cos2 = h.z * h.z;
    const float len2 = sin2 + cos2;
    if (len2 == 0.f) return 0.f;
    const float d = (sin2 + a2 * cos2) * (1.f / len2);
    return kPi * d * d;
}

// The specular parts of eval and pdf from the shared terms, each one division:
//   f_spec = D G1(wo) G1(wi) / (4 cos_o cos_i) = alpha^2 / (pi d^2 A_o A_i),  A = cos / G1 * 2;
//   VNDF pdf(h) = G1(wo) max(0, wo.h) D(h) / wo.z, times the Jacobian dh/dwi = 1 / (4 wo.h):
//   pdf_spec = G1(wo) D / (4 cos_o) = alpha^2 / (2 pi d^2 A_o).
inline float ggx_f(float a2, float pi_d2, float a_o, float a_i) {
    const float den = pi_d2 * a_o * a_i;
    return den > 0.f ? a2 / den : 0.f;
}
inline float ggx_pdf(float a2, float pi_d2, float a_o) {
    const float den = 2.f * pi_d2 * a_o;
    return den > 0.f ? a2 / den : 0.f;
}

// Reflection lobes are two-sided: mirror both directions to the upper hemisphere of wo.
inline void to_upper(vec3& wo, vec3& wi) {
    if (wo.z < 0.f) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
}

vec3 eval_lobe(const Glossy& b, vec3 wo, vec3 wi) {
    to_upper(wo, wi);
    if (wo.z <= 0.f || wi.z <= 0.f) return vec3(0.f);
    const float a2 = b.alpha * b.alpha;
    const float spec = ggx_f(a2, ggx_pi_d2(wo, wi, a2), ggx_cos_over_g1_x2(wo.z, a2), ggx_cos_over_g1_x2(wi.z, a2));
    return b.diffuse * kInvPi + b.specular * spec;
}
float pdf_lobe(const Glossy& b, vec3 wo, vec3 wi) {
    to_upper(wo, wi);
    if (wo.z <= 0.f || wi.z <= 0.f) return 0.f;
    const float a2 = b.alpha * b.alpha;
    const float ps = spec_prob(b);
    const float p_spec = ggx_pdf(a2, ggx_pi_d2(wo, wi, a2), ggx_cos_over_g1_x2(wo.z, a2));
    return ps * p_spec + (1.f - ps) * cosine_hemisphere_pdf(wi.z);
}
std::optional<BsdfSample> sample_lobe(const Glossy& b, vec3 wo, float u_lobe, vec2 u) {
    if (wo.z == 0.f) return std::nullopt;
    const bool flip = wo.z < 0.f;
    const vec3 wo_up = flip ? vec3(wo.x, wo.y, -wo.z) : wo;
    const float ps = spec_prob(b);
    vec3 wi;
    if (u_lobe < ps) {
        const vec3 h = ggx_sample_visible_normal(wo_up, b.alpha, u);
        wi = 2.f * glm::dot(wo_up, h) * h - wo_up;
    } else {
        wi = square_to_cosine_hemisphere(u);
    }
    if (!(wi.z > 0.f)) return std::nullopt;
    // eval_lobe() and pdf_lobe() with the shared terms computed once (same operations, same results).
    const float a2 = b.alpha * b.alpha;
    const float pi_d2 = ggx_pi_d2(wo_up, wi, a2);
    const float a_o = ggx_cos_over_g1_x2(wo_up.z, a2);
    const float p = ps * ggx_pdf(a2, pi_d2, a_o) + (1.f - ps) * cosine_hemisphere_pdf(wi.z);
    if (!(p > 0.f)) return std::nullopt;
    const vec3 f = b.diffuse * kInvPi + b.specular * ggx_f(a2, pi_d2, a_o, ggx_cos_over_g1_x2(wi.z, a2));
    if (flip) wi.z = -wi.z;
    return BsdfSample{f, wi, p, false};
}

}  // namespace

float alpha_from_ns(float ns) { return glm::clamp(std::sqrt(2.f / (glm::max(ns, 0.f) + 2.f)), kMinAlpha, 1.f); }

namespace detail {
vec3 eval_other(const Bsdf& bsdf, vec3 wo, vec3 wi) {
    if (const auto* g = std::get_if<Glossy>(&bsdf)) return eval_lobe(*g, wo, wi);
    if (const auto* m = std::get_if<MetallicRoughness>(&bsdf)) return eval_mr(*m, wo, wi);
    return std::holds_alternative<Lambertian>(bsdf) ? eval(bsdf, wo, wi) : vec3(0.f);
}
float pdf_other(const Bsdf& bsdf, vec3 wo, vec3 wi) {
    if (const auto* g = std::get_if<Glossy>(&bsdf)) return pdf_lobe(*g, wo, wi);
    if (const auto* m = std::get_if<MetallicRoughness>(&bsdf)) return pdf_mr(*m, wo, wi);
    return std::holds_alternative<Lambertian>(bsdf) ? pdf(bsdf, wo, wi) : 0.f;
}
std::optional<BsdfSample> sample_other(const Bsdf& bsdf, vec3 wo, float u_lobe, vec2 u) {
    if (const auto* g = std::get_if<Glossy>(&bsdf)) return sample_lobe(*g, wo, u_lobe, u);
    if (const auto* d = std::get_if<Dielectric>(&bsdf)) return sample_lobe(*d, wo, u_lobe);
    if (const auto* m = std::get_if<Mirror>(&bsdf)) return sample_lobe(*m, wo);
    if (const auto* m = std::get_if<MetallicRoughness>(&bsdf)) return sample_mr(*m, wo, u_lobe, u);
    return sample(bsdf, wo, u_lobe, u);  // Lambertian: handled inline in bsdf.h
}
}  // namespace detail

void set_base_color(Bsdf& bsdf, vec3 color) {
    if (auto* l = std::get_if<Lambertian>(&bsdf)) l->albedo = glm::clamp(color, vec3(0.f), vec3(1.f));
    if (auto* g = std::get_if<Glossy>(&bsdf)) g->diffuse = glm::clamp(color, vec3(0.f), vec3(1.f) - g->specular);
    if (auto* m = std::get_if<MetallicRoughness>(&bsdf)) m->base_color = glm::clamp(color, vec3(0.f), vec3(1.f));
}

void multiply_base_color(Bsdf& bsdf, vec3 c) {
    if (auto* l = std::get_if<Lambertian>(&bsdf)) l->albedo *= c;
    if (auto* g = std::get_if<Glossy>(&bsdf)) g->diffuse *= c;
    if (auto* m = std::get_if<MetallicRoughness>(&bsdf)) m->base_color *= c;
}

const char* bsdf_type_name(const Bsdf& bsdf) {
    static const char* names[] = {"diffuse", "mirror", "glass", "glossy", "metallic-roughness"};
    static_assert(std::variant_size_v<Bsdf> == sizeof names / sizeof names[0]);
    return names[bsdf.index()];
}

}  // namespace pv
