// core/scene/bsdf_pbr.cpp: glTF 2.0's metallic-roughness material (see core/scene/bsdf_pbr.h for the model).
#include "core/scene/bsdf_pbr.h"

#include <cfloat>

#include "core/sampling/warp.h"
#include "core/scene/ggx_albedo_table.h"
#include "core/scene/ggx_dielectric_table.h"
#include "core/scene/microfacet.h"

namespace pv {
namespace {

using MR = MetallicRoughness;

float unit_or(float x, float fallback) { return std::isfinite(x) ? glm::clamp(x, 0.f, 1.f) : fallback; }
vec3 unit(vec3 c) { return vec3(unit_or(c.x, 0.f), unit_or(c.y, 0.f), unit_or(c.z, 0.f)); }

// The dielectric layer's Fresnel reflectance at cos c >= 0 (core/scene/bsdf_pbr.h), eta the relative IOR on wo's side.
vec3 fresnel_layer(const MR& b, float c, float eta) {
    if (!b.has(MR::kSpecular)) return vec3(0.f);
    const float fd = fresnel_dielectric(c, eta);
    const float x = glm::clamp((fd - b.f0) / (1.f - b.f0), 0.f, 1.f);
    return b.specular * (b.spec_f0 + (vec3(1.f) - b.spec_f0) * x);
}

vec3 fresnel_schlick(vec3 f0, float c) {
    const float m = glm::clamp(1.f - c, 0.f, 1.f);
    const float m2 = m * m;
    return f0 + (vec3(1.f) - f0) * (m2 * m2 * m);
}

// The reflection lobes' Fresnel: the dielectric layer's and the metal's, mixed by metallic.
vec3 fresnel_reflect(const MR& b, float c, float eta) {
    vec3 f(0.f);
    if (b.has(MR::kSpecular)) f += (1.f - b.metallic) * fresnel_layer(b, c, eta);
    if (b.has(MR::kMetal)) f += b.metallic * fresnel_schlick(b.base_color, c);
    return f;
}

// Kulla-Conty multiple scattering ("Revisiting Physically Based Shading at Imageworks", SIGGRAPH 2017):
// single-scattering GGX reflects E(mu_o, alpha) of a white furnace (down to 0.31 at alpha 1); the energy lost between
// microfacets is returned by f_ms = (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)), whose albedo is exactly
// 1 - E(mu_o), scaled by the series of Fresnel-weighted bounces F_add = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)):
// for the metal F_avg = C + (1 - C) / 21 (1 for white), for the dielectric layer its Fresnel's hemispherical average
// s (F0c + (1 - F0c) x_avg(ior)). E and E_avg are bilinear in the table of core/scene/ggx_albedo_table.h (mu nodes at
// cell centres, alpha nodes at (j / 31)^2); the pdf of its cosine sample is exact (pdf_mr), so interpolation error only
// moves the albedo (< 1%), never the estimator's mean.
static_assert(kGgxAlbedoN == kGgxDielectricN, "the two albedo tables share their mu and alpha nodes");
// Bilinear in a [alpha][mu] table with the nodes above (not clamped).
float residual_lookup(const float (*t)[kGgxAlbedoN], float mu, float alpha) {
    constexpr int n = kGgxAlbedoN;
    if (!(mu >= 0.f)) mu = 0.f;  // NaN too: the int conversions below must see a finite value
    if (!(alpha >= 0.f)) alpha = 0.f;
    // Linear extrapolation over the half cells outside the outer mu nodes (E rises again toward grazing).
    const float x = glm::clamp(mu * float(n) - 0.5f, -0.5f, float(n) - 0.5f);
    const float y = glm::clamp(std::sqrt(alpha) * float(n - 1), 0.f, float(n - 1));  // roughness nodes
    const int x0 = glm::clamp(int(x), 0, n - 2), y0 = glm::min(int(y), n - 2);
    const float tx = x - float(x0), ty = y - float(y0);
    const float a = glm::mix(t[y0][x0], t[y0][x0 + 1], tx);
    const float b = glm::mix(t[y0 + 1][x0], t[y0 + 1][x0 + 1], tx);
    return glm::mix(a, b, ty);
}
// An albedo: the same, clamped to [0, 1].
float table_lookup(const float (*t)[kGgxAlbedoN], float mu, float alpha) {
    return glm::clamp(residual_lookup(t, mu, alpha), 0.f, 1.f);
}
float avg_lookup(const float* t, float alpha) {
    constexpr int n = kGgxAlbedoN;
    if (!(alpha >= 0.f)) alpha = 0.f;
    const float y = glm::clamp(std::sqrt(alpha) * float(n - 1), 0.f, float(n - 1));  // roughness nodes
    const int y0 = glm::min(int(y), n - 2);
    return glm::mix(t[y0], t[y0 + 1], y - float(y0));
}
float ggx_albedo(float mu, float alpha) { return table_lookup(kGgxAlbedo, mu, alpha); }
float ggx_albedo_avg(float alpha) { return avg_lookup(kGgxAlbedoAvg, alpha); }

// The dielectric layer's reflectance as one white furnace sees it (core/scene/ggx_dielectric_table.h): its Fresnel
// is s (F0c + (1 - F0c) x) with x = (F_exact - f0) / (1 - f0), so its single-scattering albedo is
// s (F0c E(mu) + (1 - F0c) E_x(mu)), E_x trilinear in (ior, alpha, mu); an IOR below 1 (an opaque surface facing a
// denser medium) uses 1 / ior's nodes and one above 3 the last (approximations: the base weight stays reciprocal and
// <= 1, only the furnace's sum departs from 1). Smooth (alpha 0): the exact Fresnel of the delta lobe and its average.
struct Layer {
    bool present = false;
    vec3 e_avg{0.f};  // hemispherical average of e(mu) (with the multiple scattering)
    vec3 f_add{0.f};  // the dielectric's Kulla-Conty colour term F_add (0 when smooth)
    float ggx_avg = 1.f, x_avg_alpha = 0.f;
    float ior = 1.f;  // >= 1: the IOR of the table's x
    int k0 = 0;
    float kt = 0.f;
};
Layer layer_of(const MR& b) {
    Layer l;
    if (!b.has(MR::kSpecular)) return l;
    l.present = true;
    l.ior = b.ior < 1.f ? 1.f / b.ior : b.ior;
    const float y =
        glm::clamp((l.ior - 1.f) * 0.5f * float(kGgxDielectricIorN - 1), 0.f, float(kGgxDielectricIorN - 1));
    l.k0 = glm::min(int(y), kGgxDielectricIorN - 2);
    l.kt = y - float(l.k0);
    const float x_avg = glm::mix(kFresnelDielectricAvg[l.k0], kFresnelDielectricAvg[l.k0 + 1], l.kt);
    const vec3 f0c = b.spec_f0, f_avg = b.specular * (f0c + (vec3(1.f) - f0c) * x_avg);
    if (b.alpha == 0.f) {
        l.e_avg = f_avg;
        return l;
    }
    l.ggx_avg = ggx_albedo_avg(b.alpha);
    l.x_avg_alpha = glm::mix(avg_lookup(kGgxDielectricAlbedoAvg[l.k0], b.alpha),
                             avg_lookup(kGgxDielectricAlbedoAvg[l.k0 + 1], b.alpha), l.kt);
    l.f_add = f_avg * f_avg * l.ggx_avg / (vec3(1.f) - f_avg * (1.f - l.ggx_avg));
    l.e_avg = b.specular * (f0c * l.ggx_avg + (vec3(1.f) - f0c) * l.x_avg_alpha) + l.f_add * (1.f - l.ggx_avg);
    return l;
}
// The layer's directional albedo at mu (eta: the relative IOR on wo's side, for the smooth layer's exact Fresnel).
// E_x = E x(mu) + residual: the exact normalised Fresnel x(mu) carries the steep rise toward grazing (and makes
// roughness 0 the limit), the tabulated residual what the microfacets' spread of wo.h adds to it.
vec3 layer_albedo(const MR& b, const Layer& l, float mu, float eta) {
    if (b.alpha == 0.f) return fresnel_layer(b, mu, eta);
    const float e = ggx_albedo(mu, b.alpha);
    const float x = b.f0 < 1.f ? glm::clamp((fresnel_dielectric(mu, l.ior) - b.f0) / (1.f - b.f0), 0.f, 1.f) : 0.f;
    const float ex = e * x + glm::mix(residual_lookup(kGgxDielectricAlbedo[l.k0], mu, b.alpha),
                                      residual_lookup(kGgxDielectricAlbedo[l.k0 + 1], mu, b.alpha), l.kt);
    return b.specular * (b.spec_f0 * e + (vec3(1.f) - b.spec_f0) * ex) + l.f_add * (1.f - e);
}
// The Lambert base under the layer, albedo-scaled (Kulla-Conty's reciprocal form): weight
// (1 - e(mu_o)) (1 - e(mu_i)) / (1 - e_avg), whose albedo is exactly 1 - e(mu_o): what the layer does not reflect.
vec3 base_weight(const MR& b, const Layer& l, float cos_o, float cos_i, float eta) {
    if (!l.present) return vec3(1.f);
    const vec3 t_o = glm::max(vec3(1.f) - layer_albedo(b, l, cos_o, eta), vec3(0.f));
    const vec3 t_i = glm::max(vec3(1.f) - layer_albedo(b, l, cos_i, eta), vec3(0.f));
    return t_o * t_i / glm::max(vec3(1.f) - l.e_avg, vec3(1e-6f));
}
// The multiple-scattering lobe's weight, the metal's and the dielectric layer's colour terms mixed by metallic, over
// pi (1 - E_avg); f_ms = weight (1 - E_o)(1 - E_i).
vec3 ms_weight(const MetallicRoughness& b, const Layer& l) {
    vec3 colour(0.f);
    const float e_avg = ggx_albedo_avg(b.alpha);
    if (b.has(MR::kMetal)) {
        const vec3 f_avg = b.base_color + (vec3(1.f) - b.base_color) * (1.f / 21.f);
        colour += b.metallic * f_avg * f_avg * e_avg / (vec3(1.f) - f_avg * (1.f - e_avg));
    }
    if (l.present) colour += (1.f - b.metallic) * l.f_add;
    return colour * (kInvPi / glm::max(1.f - e_avg, 1e-6f));
}
bool has_ms(const MetallicRoughness& b) {
    return b.alpha > 0.f && (b.has(MetallicRoughness::kMetal) || b.has(MetallicRoughness::kSpecular));
}
// wo and wi seen from wo's side (wo.z >= 0), and the relative IOR there.
struct Side {
    vec3 wo, wi;
    float eta;
    bool flipped;
};
Side side_of(const MR& b, vec3 wo, vec3 wi) {
    const bool flipped = wo.z < 0.f;
    if (flipped) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    return {wo, wi, b.solid() && flipped ? 1.f / b.ior : b.ior, flipped};
}

// Lobe selection probabilities for wo (cos_o > 0): reflection (dielectric specular + metal, one GGX distribution),
// the metal's multiple scattering (its albedo), diffuse, transmission, in proportion to the luminance of each lobe's
// weight at normal-ish incidence; a present lobe has at least a small probability, so that sample() reaches wherever
// eval() is nonzero.
struct LobeProbs {
    float r = 0.f, m = 0.f, d = 0.f, t = 0.f;
};
LobeProbs lobe_probs(const MR& b, const Layer& l, float cos_o, float eta) {
    constexpr float kFloor = 1e-3f;
    LobeProbs p;
    const vec3 fl = l.present ? layer_albedo(b, l, cos_o, eta) : vec3(0.f);
    if (b.has(MR::kSpecular) || b.has(MR::kMetal)) p.r = glm::max(luminance(fresnel_reflect(b, cos_o, eta)), kFloor);
    const float base = (1.f - b.metallic) * luminance(b.base_color * (vec3(1.f) - fl));
    if (b.has(MR::kDiffuse)) p.d = glm::max((1.f - b.transmission) * base, kFloor);
    if (b.has(MR::kTransmission)) p.t = glm::max(b.transmission * base, kFloor);
    if (has_ms(b)) p.m = luminance(ms_weight(b, l)) * kPi * (1.f - ggx_albedo(cos_o, b.alpha));
    const float sum = p.r + p.m + p.d + p.t;
    if (!(sum > 0.f)) return LobeProbs{};
    const float inv = 1.f / sum;
    p.r *= inv;
    p.m *= inv;
    p.d *= inv;
    p.t *= inv;
    return p;
}

// GGX reflection f without Fresnel, D G1 G1 / (4 cos_o cos_i), and its VNDF pdf G1(wo) D / (4 cos_o); wo.z, wi.z > 0.
float ggx_reflect_f(vec3 wo, vec3 wi, float alpha, float* pdf) {
    const vec3 h = glm::normalize(wo + wi);
    const float d = ggx_d(h, alpha), g1o = ggx_g1(wo, alpha);
    if (pdf) *pdf = g1o * d / (4.f * wo.z);
    return d * g1o * ggx_g1(wi, alpha) / (4.f * wo.z * wi.z);
}

// Rough refraction (Walter et al. 2007; pbrt-v4's DielectricBxDF): wo.z > 0 > wi.z, eta = n(wi side) / n(wo side).
// Returns false where wi is not a refraction of wo about any visible microfacet.
struct Refraction {
    vec3 wm;
    float f;    // D G1 G1 |wi.wm wo.wm| / (|cos_i| cos_o denom^2) / eta^2, without (1 - F)
    float pdf;  // VNDF pdf of wm times dwm/dwi
};
bool ggx_refract(vec3 wo, vec3 wi, float alpha, float eta, Refraction& out) {
    vec3 wm = wi * eta + wo;
    const float len2 = glm::dot(wm, wm);
    if (!(len2 > 0.f)) return false;
    wm *= 1.f / std::sqrt(len2);
    if (wm.z < 0.f) wm = -wm;
    const float o_m = glm::dot(wo, wm), i_m = glm::dot(wi, wm);
    if (!(o_m > 0.f) || !(i_m < 0.f)) return false;
    const float denom = i_m + o_m / eta;
    const float denom2 = denom * denom;
    if (!(denom2 > 0.f)) return false;
    const float d = ggx_d(wm, alpha), g1o = ggx_g1(wo, alpha);
    out.wm = wm;
    out.f = d * g1o * ggx_g1(wi, alpha) * std::fabs(i_m * o_m) / (std::fabs(wi.z) * wo.z * denom2) / (eta * eta);
    out.pdf = g1o * d * o_m / wo.z * std::fabs(i_m) / denom2;
    return std::isfinite(out.f) && std::isfinite(out.pdf);
}

// eval and pdf (of the non-delta lobes) from wo's side.
vec3 eval_side(const MR& b, const Layer& l, const Side& s, float* pdf_out) {
    const vec3 wo = s.wo, wi = s.wi;
    float pdf = 0.f;
    vec3 f(0.f);
    if (wo.z > 0.f) {
        const LobeProbs p = pdf_out ? lobe_probs(b, l, wo.z, s.eta) : LobeProbs{};  // eval() needs no pdf
        if (wi.z > 0.f) {
            if (b.has(MR::kDiffuse)) {
                f += ((1.f - b.metallic) * (1.f - b.transmission) * kInvPi) * b.base_color *
                     base_weight(b, l, wo.z, wi.z, s.eta);
                pdf += p.d * cosine_hemisphere_pdf(wi.z);
            }
            if (b.alpha > 0.f && (b.lobes & (MR::kSpecular | MR::kMetal))) {
                float pr = 0.f;
                const float g = ggx_reflect_f(wo, wi, b.alpha, &pr);
                const vec3 h = glm::normalize(wo + wi);
                f += fresnel_reflect(b, glm::dot(wo, h), s.eta) * g;
                pdf += p.r * pr;
                if (has_ms(b)) {
                    const float lost = (1.f - ggx_albedo(wo.z, b.alpha)) * (1.f - ggx_albedo(wi.z, b.alpha));
                    f += ms_weight(b, l) * lost;
                    pdf += p.m * cosine_hemisphere_pdf(wi.z);
                }
            }
        } else if (wi.z < 0.f && b.alpha > 0.f && b.has(MR::kTransmission)) {
            const vec3 tint = ((1.f - b.metallic) * b.transmission) * b.base_color;
            if (b.thin_walled) {
                // The reflection lobe mirrored through the surface: straight through, blurred by roughness.
                const vec3 wr(wi.x, wi.y, -wi.z);
                float pt = 0.f;
                const float g = ggx_reflect_f(wo, wr, b.alpha, &pt);
                const vec3 h = glm::normalize(wo + wr);
                f += tint * (vec3(1.f) - fresnel_layer(b, glm::dot(wo, h), s.eta)) * g;
                pdf += p.t * pt;
            } else {
                Refraction r;
                if (ggx_refract(wo, wi, b.alpha, s.eta, r)) {
                    f += tint * (vec3(1.f) - fresnel_layer(b, glm::dot(wo, r.wm), s.eta)) * r.f;
                    pdf += p.t * r.pdf;
                }
            }
        }
    }
    if (pdf_out) *pdf_out = pdf;
    return f;
}

}  // namespace

void prepare_metallic_roughness(MetallicRoughness& m) {
    m.base_color = unit(m.base_color);
    m.metallic = unit_or(m.metallic, 1.f);
    m.roughness = unit_or(m.roughness, 1.f);
    m.specular = unit_or(m.specular, 1.f);
    m.specular_color = unit(m.specular_color);
    m.transmission = unit_or(m.transmission, 0.f);
    m.attenuation_color = unit(m.attenuation_color);
    if (!(m.ior > 0.f) || !std::isfinite(m.ior)) m.ior = 1.5f;
    if (!(m.attenuation_distance > 0.f)) m.attenuation_distance = INFINITY;
    m.alpha = m.roughness == 0.f ? 0.f : glm::max(m.roughness * m.roughness, kMinAlpha);
    const float r = (m.ior - 1.f) / (m.ior + 1.f);
    m.f0 = r * r;
    m.spec_f0 = glm::min(m.f0 * m.specular_color, vec3(1.f));
    uint8_t lobes = 0;
    if (m.metallic < 1.f && m.transmission < 1.f) lobes |= MR::kDiffuse;
    if (m.metallic < 1.f && m.specular > 0.f && m.f0 > 0.f) lobes |= MR::kSpecular;
    if (m.metallic > 0.f) lobes |= MR::kMetal;
    if (m.metallic < 1.f && m.transmission > 0.f) lobes |= MR::kTransmission;
    m.lobes = lobes;
    m.delta_only = m.alpha == 0.f && !m.has(MR::kDiffuse);
    m.lambert_only = m.lobes == MR::kDiffuse && m.metallic == 0.f && m.transmission == 0.f;
    m.sigma = vec3(0.f);
    if (m.solid() && std::isfinite(m.attenuation_distance))
        for (int c = 0; c < 3; ++c)
            m.sigma[c] = -std::log(glm::max(m.attenuation_color[c], 1e-30f)) / m.attenuation_distance;
}

void apply_metallic_roughness_texel(MetallicRoughness& m, float metallic, float roughness) {
    m.metallic *= unit_or(metallic, 1.f);
    m.roughness *= unit_or(roughness, 1.f);
    if (m.alpha > 0.f) m.alpha = glm::max(m.roughness * m.roughness, kMinAlpha);
}

MetallicRoughness make_metallic_roughness(MetallicRoughness m) {
    prepare_metallic_roughness(m);
    return m;
}

namespace detail {

vec3 eval_mr(const MetallicRoughness& b, vec3 wo, vec3 wi) {
    if (b.lambert_only) return lambert_eval(b.base_color, wo, wi);
    return eval_side(b, layer_of(b), side_of(b, wo, wi), nullptr);
}

float pdf_mr(const MetallicRoughness& b, vec3 wo, vec3 wi) {
    if (b.lambert_only) return lambert_pdf(wo, wi);
    float pdf = 0.f;
    eval_side(b, layer_of(b), side_of(b, wo, wi), &pdf);
    return pdf;
}

std::optional<BsdfSample> sample_mr(const MetallicRoughness& b, vec3 wo_in, float u_lobe, vec2 u) {
    if (b.lambert_only) return lambert_sample(b.base_color, wo_in, u);
    if (!(std::fabs(wo_in.z) >= FLT_MIN)) return std::nullopt;  // zero or denormal: a delta f = 1/|cos| overflows
    const Side s = side_of(b, wo_in, vec3(0.f));
    const vec3 wo = s.wo;
    const float cos_o = wo.z;
    const Layer l = layer_of(b);
    const LobeProbs p = lobe_probs(b, l, cos_o, s.eta);
    const bool delta = b.alpha == 0.f;
    auto finish = [&](vec3 wi, vec3 f, float pdf, bool is_delta, float eta) -> std::optional<BsdfSample> {
        if (s.flipped) wi.z = -wi.z;
        if (!is_delta) f = eval_side(b, l, side_of(b, wo_in, wi), &pdf);
        if (!(pdf > 0.f) || !is_finite(f)) return std::nullopt;
        return BsdfSample{f, wi, pdf, is_delta, eta};
    };
    if (u_lobe < p.r) {
        if (delta) {
            const vec3 wi(-wo.x, -wo.y, wo.z);
            return finish(wi, fresnel_reflect(b, cos_o, s.eta) / cos_o, p.r, true, 1.f);
        }
        const vec3 h = ggx_sample_visible_normal(wo, b.alpha, u);
        const vec3 wi = 2.f * glm::dot(wo, h) * h - wo;
        if (!(wi.z > 0.f)) return std::nullopt;
        return finish(wi, vec3(0.f), 0.f, false, 1.f);
    }
    if (u_lobe < p.r + p.m) {  // the metal's multiple scattering: cosine-distributed
        const vec3 wi = square_to_cosine_hemisphere(u);
        if (!(wi.z > 0.f)) return std::nullopt;
        return finish(wi, vec3(0.f), 0.f, false, 1.f);
    }
    if (u_lobe < p.r + p.m + p.d || !(p.t > 0.f)) {
        if (!(p.d > 0.f)) return std::nullopt;
        const vec3 wi = square_to_cosine_hemisphere(u);
        if (!(wi.z > 0.f)) return std::nullopt;
        return finish(wi, vec3(0.f), 0.f, false, 1.f);
    }
    // Transmission.
    const vec3 tint = ((1.f - b.metallic) * b.transmission) * b.base_color;
    if (b.thin_walled) {
        if (delta) {
            const vec3 t = vec3(1.f) - fresnel_layer(b, cos_o, s.eta);
            return finish(-wo, tint * t / cos_o, p.t, true, 1.f);
        }
        const vec3 h = ggx_sample_visible_normal(wo, b.alpha, u);
        const vec3 wr = 2.f * glm::dot(wo, h) * h - wo;
        if (!(wr.z > 0.f)) return std::nullopt;
        return finish(vec3(wr.x, wr.y, -wr.z), vec3(0.f), 0.f, false, 1.f);
    }
    const float eta = s.eta;
    const vec3 m = delta ? vec3(0.f, 0.f, 1.f) : ggx_sample_visible_normal(wo, b.alpha, u);
    const float cos_m = glm::dot(wo, m);
    if (!(cos_m > 0.f)) return std::nullopt;
    const float sin2_t = glm::max(0.f, 1.f - cos_m * cos_m) / (eta * eta);
    if (sin2_t >= 1.f) return std::nullopt;  // total internal reflection: (1 - F) = 0
    const float cos_t = std::sqrt(1.f - sin2_t);
    const vec3 wi = glm::normalize(-wo / eta + (cos_m / eta - cos_t) * m);
    if (!(wi.z < 0.f)) return std::nullopt;
    if (delta) {
        const vec3 t = vec3(1.f) - fresnel_layer(b, cos_o, eta);
        return finish(wi, tint * t / (eta * eta * std::fabs(wi.z)), p.t, true, eta);
    }
    return finish(wi, vec3(0.f), 0.f, false, eta);
}

}  // namespace detail
}  // namespace pv
