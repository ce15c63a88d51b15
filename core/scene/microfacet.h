// core/scene/microfacet.h: the building blocks the BSDFs share (core/scene/bsdf.h's lobes and the
// metallic-roughness material of core/scene/bsdf_pbr.h): the sample record, Lambert's lobe, GGX and Fresnel. Below
// both, so that neither includes the other's implementation. Conventions as in bsdf.h.
#pragma once

#include <optional>

#include "core/base/math.h"
#include "core/sampling/warp.h"

namespace pv {

struct BsdfSample {
    vec3 f{0.f};
    vec3 wi{0.f};
    float pdf = 0.f;
    bool is_delta = false;
    float eta = 1.f;  // relative IOR crossed (1 unless refracted); for Russian roulette's eta scale
};

// Whether wo and wi are strictly on the same side, where alone the reflection-only lobes (Lambertian, Glossy: the
// ones a base-colour texture applies to, with transmits() false) can be nonzero: where it is false their eval() is zero
// whatever the colour, so a caller can skip a direction before looking the colour up.
inline bool reflects(vec3 wo, vec3 wi) { return wo.z > 0.f ? wi.z > 0.f : (wo.z < 0.f && wi.z < 0.f); }

// Lambert's lobe f = albedo / pi, two-sided (nonzero where wo and wi are strictly on the same side), sampled by the
// cosine; the Lambertian BSDF and a metallic-roughness material that is only its Lambert base.
inline vec3 lambert_eval(vec3 albedo, vec3 wo, vec3 wi) { return reflects(wo, wi) ? albedo * kInvPi : vec3(0.f); }
inline float lambert_pdf(vec3 wo, vec3 wi) {
    if (wo.z > 0.f) return cosine_hemisphere_pdf(wi.z);
    return wo.z < 0.f ? cosine_hemisphere_pdf(-wi.z) : 0.f;
}
inline std::optional<BsdfSample> lambert_sample(vec3 albedo, vec3 wo, vec2 u) {
    if (wo.z == 0.f) return std::nullopt;
    vec3 wi = square_to_cosine_hemisphere(u);
    if (!(wi.z > 0.f)) return std::nullopt;  // wi.z == 0 at the disk's rim: a grazing, useless direction
    const float p = wi.z * kInvPi;           // cosine_hemisphere_pdf(wi.z)
    if (wo.z < 0.f) wi.z = -wi.z;
    return BsdfSample{albedo * kInvPi, wi, p, false};
}

// GGX (Trowbridge-Reitz) helpers, isotropic; exposed for tests.
float ggx_d(vec3 h, float alpha);
float ggx_g1(vec3 w, float alpha);
vec3 ggx_sample_visible_normal(vec3 wo, float alpha, vec2 u);
// Unpolarised Fresnel reflectance of a dielectric interface; cos_i signed (< 0: from inside), eta = n_in/n_out.
float fresnel_dielectric(float cos_i, float eta);
constexpr float kMinAlpha = 1e-3f;

}  // namespace pv
