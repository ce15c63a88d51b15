// core/scene/bsdf.h: surface scattering, a closed set of lobes that MTL files ask for.
// Conventions: local shading frame, +z = shading normal; wo and wi both point away from the surface;
// eval() returns f WITHOUT the cosine; sample() returns {f, wi, pdf, is_delta} (not a pre-divided weight).
// pdfs are per solid angle. Delta lobes: eval() and pdf() return 0. Colours are linear RGB.
#pragma once

#include <optional>
#include <string>
#include <variant>

#include "core/base/math.h"
#include "core/sampling/warp.h"
#include "core/scene/bsdf_pbr.h"
#include "core/scene/medium.h"
#include "core/scene/microfacet.h"

namespace pv {

// BsdfSample: core/scene/microfacet.h.

// Ideal diffuse reflection f = albedo/pi, cosine-weighted sampling.
struct Lambertian {
    vec3 albedo{0.8f};
};

// Perfect specular reflection with constant reflectance.
struct Mirror {
    vec3 reflectance{1.f};
};

// Smooth dielectric interface (glass) with exact unpolarised Fresnel; eta = n_inside / n_outside.
// Radiance crossing the interface is scaled by 1/eta^2 (radiance transport), so it is not reciprocal in f.
struct Dielectric {
    float eta = 1.5f;
};

// A diffuse base plus a GGX microfacet specular lobe, summed: f = diffuse/pi + specular * D G2 / (4 cos_o cos_i).
// "specular" is the constant Fresnel reflectance (MTL Ks). The loader keeps diffuse + specular <= 1 per channel,
// which with GGX's single-scattering albedo <= 1 bounds the material's albedo by 1. Sampling picks a lobe in
// proportion to the luminance of each weight; the GGX lobe samples visible normals (Heitz 2018).
// alpha is GGX roughness (alpha = 0 is not allowed: use Mirror).
struct Glossy {
    vec3 diffuse{0.f};
    vec3 specular{0.04f};
    float alpha = 0.2f;
};

// MetallicRoughness: glTF 2.0's material, core/scene/bsdf_pbr.h.
// Reflection-only lobes are two-sided (they treat wo.z < 0 by mirroring); the dielectric uses the sign of wo.z
// to tell outside (+) from inside (-).
using Bsdf = std::variant<Lambertian, Mirror, Dielectric, Glossy, MetallicRoughness>;

// f(wo, wi), without the cosine. Zero for delta lobes.
inline vec3 eval(const Bsdf& bsdf, vec3 wo, vec3 wi);
// Solid-angle pdf of sample() producing wi. Zero for delta lobes.
inline float pdf(const Bsdf& bsdf, vec3 wo, vec3 wi);
// Samples wi given wo; u_lobe picks a lobe or the reflect/refract branch, u the direction.
// Returns nothing where no direction can be produced (grazing wo, below-surface sample, zero weight).
inline std::optional<BsdfSample> sample(const Bsdf& bsdf, vec3 wo, float u_lobe, vec2 u);
// True if every lobe is a delta function (no light sampling is useful).
inline bool is_delta(const Bsdf& bsdf) {
    if (std::holds_alternative<Mirror>(bsdf) || std::holds_alternative<Dielectric>(bsdf)) return true;
    const auto* m = std::get_if<MetallicRoughness>(&bsdf);
    return m && m->delta_only;
}
// The relative IOR n_inside / n_outside of a BSDF that tells inside (wo.z < 0) from outside (the dielectric, a solid
// transmissive metallic-roughness material), whose shading frame must not be flipped toward wo; 0 for the two-sided
// ones.
inline float oriented_eta(const Bsdf& bsdf) {
    if (const auto* d = std::get_if<Dielectric>(&bsdf)) return d->eta;
    const auto* m = std::get_if<MetallicRoughness>(&bsdf);
    return m && m->solid() ? m->ior : 0.f;
}
// A metallic-roughness material that is exactly a Lambertian (MetallicRoughness::lambert_only): one lobe.
inline bool lambert_only(const Bsdf& bsdf) {
    const auto* m = std::get_if<MetallicRoughness>(&bsdf);
    return m && m->lambert_only;
}
// Whether eval() can be nonzero for wo and wi on opposite sides (a transmission lobe that is not a delta lobe).
inline bool transmits(const Bsdf& bsdf) {
    const auto* m = std::get_if<MetallicRoughness>(&bsdf);
    return m && m->has(MetallicRoughness::kTransmission) && m->alpha > 0.f;
}
// reflects(wo, wi): core/scene/microfacet.h.
const char* bsdf_type_name(const Bsdf& bsdf);
// Sets the diffuse colour (Lambertian albedo, Glossy diffuse clamped so diffuse + specular <= 1, MetallicRoughness
// base colour clamped to [0, 1]); others unchanged.
void set_base_color(Bsdf& bsdf, vec3 color);
// Multiplies that diffuse colour by `c` in [0, 1]^3 (a glTF COLOR_0 over the factor or texel); the products stay
// within set_base_color's bounds.
void multiply_base_color(Bsdf& bsdf, vec3 c);

// GGX (ggx_d, ggx_g1, ggx_sample_visible_normal) and fresnel_dielectric: core/scene/microfacet.h.
// Blinn-Phong exponent Ns -> GGX alpha: alpha = sqrt(2 / (Ns + 2)) (Walter et al. 2007, eq. 34's Beckmann
// correspondence, applied to GGX), clamped to [kMinAlpha, 1].
float alpha_from_ns(float ns);

// KHR_texture_transform on one texture reference: uv' = col0 * uv.x + col1 * uv.y + offset (the extension's offset,
// rotation and scale composed), read from texture-coordinate set `set` (0: TEXCOORD_0 / OBJ vt, 1: TEXCOORD_1).
// The default is the identity on set 0, which OBJ textures use.
struct UvTransform {
    vec2 col0{1.f, 0.f};
    vec2 col1{0.f, 1.f};
    vec2 offset{0.f};
    uint32_t set = 0;
    vec2 apply(vec2 uv) const { return col0 * uv.x + col1 * uv.y + offset; }
    bool is_identity() const {
        return col0 == vec2(1.f, 0.f) && col1 == vec2(0.f, 1.f) && offset == vec2(0.f) && set == 0;
    }
    bool operator==(const UvTransform& o) const {
        return col0 == o.col0 && col1 == o.col1 && offset == o.offset && set == o.set;
    }
};

// A material: a BSDF plus optional emission. Only what the MTL asked for is present.
struct Material {
    std::string name = "default";
    Bsdf bsdf = Lambertian{};
    vec3 emission{0.f};  // radiance leaving the front face (Ke)
    bool two_sided_emission = false;
    uint32_t base_color_texture = kNoIndex;  // index into Scene::textures (map_Kd), replaces the base colour
    uint32_t alpha_texture = kNoIndex;       // index into Scene::textures (map_d): stochastic cut-out
    // glTF's metallicRoughnessTexture (linear: B metallic, G roughness), read at the same uv as the base colour; it
    // scales a MetallicRoughness BSDF's factors (apply_metallic_roughness_texel). kNoIndex: the factors alone.
    uint32_t metallic_roughness_texture = kNoIndex;
    // glTF's emissiveTexture (sRGB, decoded to linear): the emitted radiance at a point is emission x its texel
    // (emission already holds emissiveFactor x KHR_materials_emissive_strength). kNoIndex: uniform emission.
    uint32_t emissive_texture = kNoIndex;
    UvTransform emissive_uv;  // where emissive_texture is read (Scene::texcoord)
    // glTF's normalTexture (linear: a tangent-space normal, 2 x texel - 1), read at the base colour's uv; its x and y
    // are scaled by normal_scale. kNoIndex: the interpolated normal (no per-hit work).
    uint32_t normal_texture = kNoIndex;
    float normal_scale = 1.f;
    // KHR_materials_clearcoat's clearcoatTexture (linear: R scales clearcoat) and clearcoatRoughnessTexture (linear: G
    // scales the coat's roughness), and KHR_materials_sheen's sheenColorTexture (sRGB, decoded: RGB scales the sheen
    // colour) and sheenRoughnessTexture (linear: A scales the sheen roughness), read at the base colour's uv; they
    // scale a MetallicRoughness BSDF's layer factors (apply_clearcoat_texel, apply_sheen_texel). kNoIndex: the factor.
    uint32_t clearcoat_texture = kNoIndex;
    uint32_t clearcoat_roughness_texture = kNoIndex;
    uint32_t sheen_color_texture = kNoIndex;
    uint32_t sheen_roughness_texture = kNoIndex;
    bool has_layer_textures() const {
        return clearcoat_texture != kNoIndex || clearcoat_roughness_texture != kNoIndex ||
               sheen_color_texture != kNoIndex || sheen_roughness_texture != kNoIndex;
    }
    // The light group its emission is credited to (core/render/light_groups.h); empty: the material's name.
    std::string light_group;
    // The medium inside a closed mesh of this material (docs/media.md), entered by a path that transmits through it
    // (glass, or a metallic-roughness material with transmission); empty: none. It takes the place of the
    // material's KHR_materials_volume attenuation.
    HomogeneousMedium medium;
    bool has_emission() const { return !is_black(emission); }
};

// ---- Inline dispatch: the Lambertian case (most surfaces) is a few instructions in the caller; the other
// lobes are out of line in bsdf.cpp.
namespace detail {
vec3 eval_other(const Bsdf& bsdf, vec3 wo, vec3 wi);
float pdf_other(const Bsdf& bsdf, vec3 wo, vec3 wi);
std::optional<BsdfSample> sample_other(const Bsdf& bsdf, vec3 wo, float u_lobe, vec2 u);
}  // namespace detail

inline vec3 eval(const Bsdf& bsdf, vec3 wo, vec3 wi) {
    if (const auto* l = std::get_if<Lambertian>(&bsdf)) return lambert_eval(l->albedo, wo, wi);
    return detail::eval_other(bsdf, wo, wi);
}

inline float pdf(const Bsdf& bsdf, vec3 wo, vec3 wi) {
    if (std::holds_alternative<Lambertian>(bsdf)) return lambert_pdf(wo, wi);
    return detail::pdf_other(bsdf, wo, wi);
}

inline std::optional<BsdfSample> sample(const Bsdf& bsdf, vec3 wo, float u_lobe, vec2 u) {
    if (const auto* l = std::get_if<Lambertian>(&bsdf)) return lambert_sample(l->albedo, wo, u);
    return detail::sample_other(bsdf, wo, u_lobe, u);
}

}  // namespace pv
