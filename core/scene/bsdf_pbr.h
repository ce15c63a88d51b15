// core/scene/bsdf_pbr.h: glTF 2.0's metallic-roughness material (the specification's Appendix B, with
// KHR_materials_ior, _specular, _transmission and _volume), one alternative of Bsdf (core/scene/bsdf.h, whose
// conventions hold: local frame, +z the shading normal, eval() without the cosine, delta lobes absent from eval() and
// pdf()).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>

#include "core/base/math.h"

// The model:
//   f = (1 - metallic) * dielectric + metallic * metal
//   metal      = GGX reflection, Schlick Fresnel toward base_color:  F_m(c) = C + (1 - C)(1 - c)^5, c = wo.h
//              + Kulla-Conty multiple scattering  F_add,m (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg))
//   dielectric = GGX reflection weighted by F(wo.h)
//              + Kulla-Conty multiple scattering  F_add,d (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg))
//              + (1 - transmission) * C/pi (1 - e(mu_o)) (1 - e(mu_i)) / (1 - e_avg)       (albedo-scaled Lambert base)
//              + transmission * C * (1 - F(wo.h)) * GGX transmission               (thin: mirrored; solid: refracted)
//   F(c) = specular * (F0c + (1 - F0c) x(c)),  x(c) = (F_exact(c) - f0) / (1 - f0),  f0 = ((ior - 1) / (ior + 1))^2,
//          F0c = min(f0 * specular_color, 1): the exact dielectric Fresnel with ior, whose normal-incidence value is
//          recoloured and scaled as KHR_materials_specular asks (specular = 1, specular_color = 1: F = F_exact).
//   E(mu), E_avg: the Fresnel-less single-scattering GGX albedo and its hemispherical average
//          (core/scene/ggx_albedo_table.h); F_add = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)), with F_avg the Fresnel's
//          hemispherical average (metal: C + (1 - C) / 21; dielectric: specular (F0c + (1 - F0c) x_avg(ior))).
//   e(mu) = the dielectric layer's directional albedo, its GGX reflection plus its multiple scattering:
//          specular (F0c E(mu) + (1 - F0c) E_x(mu)) + F_add,d (1 - E(mu)), E_x the albedo weighted by x
//          (core/scene/ggx_dielectric_table.h, trilinear in ior, alpha, mu); e_avg its hemispherical average.
//          Roughness 0: e(mu) = F(mu), e_avg = F_avg exactly.
// The base sees only the light the layer does not reflect: its albedo is exactly (1 - e(mu_o)) (Kulla-Conty's
// reciprocal albedo scaling, as OpenPBR layers its coat and specular over the base), so a white material
// (base colour 1, transmission 0) reflects 1 of a white furnace at every roughness, metallic and angle (within the
// tables' interpolation, < 0.1% at IOR 1.5: tests/scene/test_bsdf_pbr.cpp, WhiteSphereRingsAreOne).
// Where this departs from the specification's Appendix B, and why:
//  * Appendix B mixes the base by (1 - F(v.h)) of the specular microfacet, which is not reciprocal and can reflect
//    more than 1 at grazing incidence, and loses what the single-scattering GGX layer does not reflect (a white
//    plastic reflected 0.83-0.92 of a white furnace, 0.95 even when smooth): here the base is albedo-scaled instead.
//  * Appendix B's GGX is single-scattering; both reflection lobes here add Kulla-Conty's multiple scattering, so rough
//    materials are brighter (a white metal of roughness 1 reflected 0.31 at normal incidence, now 1), as in Cycles'
//    Principled BSDF and OpenPBR.
//  * Not compensated yet: the transmission lobes (a white thin or solid transmissive material still loses the
//    multiple scattering of rough refraction). An IOR outside [1, 3] uses the table's nearest IOR (1 / ior below 1),
//    an approximation that moves the furnace's sum slightly from 1 (albedos stay <= 1 at IOR 1.05, 1.5 and 3:
//    AlbedoAtMostOneEverywhere).
// alpha = roughness^2 (>= kMinAlpha); roughness 0 makes the reflection and transmission lobes delta lobes. Only lobes
// whose parameters are non-zero are present (lobes below).
// Solid transmission (thin_walled false) is oriented like Dielectric: wo.z < 0 is inside, where the relative IOR is
// 1 / ior; refracted radiance is scaled by 1/eta^2 as Dielectric's is. Other configurations are two-sided.
// Beer-Lambert attenuation (attenuation_color/distance, KHR_materials_volume) is applied by the path tracer to the
// segments a path travels inside a solid one, entered and left by refraction.

namespace pv {

struct BsdfSample;

struct MetallicRoughness {
    vec3 base_color{1.f};
    float metallic = 1.f;
    float roughness = 1.f;     // perceptual; GGX alpha = roughness^2 clamped to >= kMinAlpha, or delta lobes at 0
    float ior = 1.5f;          // KHR_materials_ior
    float specular = 1.f;      // KHR_materials_specular specularFactor
    vec3 specular_color{1.f};  // KHR_materials_specular specularColorFactor
    float transmission = 0.f;  // KHR_materials_transmission
    bool thin_walled = true;   // KHR_materials_volume thickness 0 -> thin
    vec3 attenuation_color{1.f};
    float attenuation_distance = INFINITY;

    // Derived by prepare_metallic_roughness(); call it after changing any field above except base_color.
    enum Lobe : uint8_t { kDiffuse = 1, kSpecular = 2, kMetal = 4, kTransmission = 8 };
    float alpha = 1.f;        // GGX alpha; 0 when roughness == 0 (reflection and transmission are delta lobes)
    float f0 = 0.04f;         // ((ior - 1) / (ior + 1))^2
    vec3 spec_f0{0.04f};      // min(f0 * specular_color, 1), before the specular factor
    uint8_t lobes = kMetal;   // the lobes present
    bool delta_only = false;  // every present lobe is a delta lobe (is_delta())
    // Only the Lambert base, with weight 1 (metallic 0, transmission 0, no dielectric Fresnel: specular 0 or IOR 1):
    // exactly Lambertian{base_color}, evaluated and sampled by the same code, so it renders the same image.
    bool lambert_only = false;
    // Beer-Lambert absorption coefficient inside a solid one, -ln(attenuation_color) / attenuation_distance per unit
    // length (0: none); the integrator applies exp(-sigma t) to path segments inside (core/render/integrator.cpp).
    vec3 sigma{0.f};

    bool has(Lobe l) const { return (lobes & l) != 0; }
    bool solid() const { return has(kTransmission) && !thin_walled; }
};

// Clamps the parameters (colours and factors to [0, 1], a non-finite or non-positive ior to 1.5, a non-positive or
// NaN attenuation distance to infinity) and computes the derived fields.
void prepare_metallic_roughness(MetallicRoughness& m);
MetallicRoughness make_metallic_roughness(MetallicRoughness m);  // prepared copy
// glTF's metallicRoughnessTexture at a hit: multiplies metallic by the texel's B and roughness by its G (linear, in
// [0, 1]) on a prepared material, keeping its lobes (a lobe whose factor the texel zeroes weighs 0) and its
// delta-ness (a texel roughness of 0 on a rough material gives kMinAlpha), so that the untextured material's
// is_delta() and oriented_eta() stay valid for the textured copy.
void apply_metallic_roughness_texel(MetallicRoughness& m, float metallic, float roughness);

namespace detail {
vec3 eval_mr(const MetallicRoughness& b, vec3 wo, vec3 wi);
float pdf_mr(const MetallicRoughness& b, vec3 wo, vec3 wi);
std::optional<BsdfSample> sample_mr(const MetallicRoughness& b, vec3 wo, float u_lobe, vec2 u);
}  // namespace detail

}  // namespace pv
