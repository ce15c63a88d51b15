// core/scene/material_params.h: the editable face of a Bsdf, and the one conversion between it and a Bsdf. Every place
// that builds a BSDF from user parameters (the viewer's material editor, scene.json material overrides, the MTL
// loader's glossy materials) goes through make_bsdf(), so the promises of core/scene/bsdf.h hold everywhere (the
// invariants at BsdfParams).
#pragma once

#include "core/scene/bsdf.h"

namespace pv {

enum class BsdfType : int { Diffuse = 0, Glossy = 1, Mirror = 2, Glass = 3, MetallicRoughness = 4 };

// The invariants make_bsdf() keeps: colours in [0, 1], a glossy material's diffuse + specular <= 1 per channel (its
// albedo stays <= 1), GGX roughness in [kMinAlpha, 1], and a positive finite IOR (a metallic-roughness material:
// factors in [0, 1] as well).
struct BsdfParams {
    BsdfType type = BsdfType::Diffuse;
    vec3 base{0.8f};         // diffuse albedo; a mirror's reflectance; metallic-roughness: base colour
    vec3 specular{0.04f};    // glossy: the GGX lobe's Fresnel reflectance (MTL Ks); metallic-roughness: specular colour
    float roughness = 0.2f;  // glossy: GGX alpha; metallic-roughness: perceptual roughness (alpha = roughness^2)
    float ior = 1.5f;        // glass: n_inside / n_outside; metallic-roughness: its IOR
    // metallic-roughness only (core/scene/bsdf_pbr.h):
    float metallic = 0.f;
    float transmission = 0.f;
    float specular_weight = 1.f;  // KHR_materials_specular's specularFactor
    bool thin_walled = true;
    vec3 attenuation_color{1.f};
    float attenuation_distance = INFINITY;
    float clearcoat = 0.f;  // KHR_materials_clearcoat clearcoatFactor and clearcoatRoughnessFactor
    float clearcoat_roughness = 0.f;
    vec3 sheen_color{0.f};  // KHR_materials_sheen sheenColorFactor and sheenRoughnessFactor
    float sheen_roughness = 0.f;
};

// The parameters of `bsdf` (the fields its type does not use keep their defaults, except that a mirror's
// reflectance is also its specular colour, so switching mirror <-> glossy keeps the colour).
BsdfParams bsdf_params(const Bsdf& bsdf);
// The BSDF of `p`, clamped to the invariants above (a non-finite or non-positive IOR becomes 1.5; callers that
// read user input reject those first with a message).
Bsdf make_bsdf(const BsdfParams& p);
// `p` switched to type `t` (the panel's type combo): the fields the two types read differently are carried over by
// meaning, not copied: a metallic-roughness material's specular colour (1 by default) is not a glossy lobe's Fresnel
// reflectance (0.04 for a dielectric), nor its perceptual roughness a GGX alpha. Into metallic-roughness: a diffuse
// or glossy material is a dielectric (metallic 0, specular colour 1, roughness 1 or sqrt(alpha)), a mirror a smooth
// metal of its colour, glass a smooth transmissive one. Out of it into glossy: base colour x (1 - metallic) over a
// specular of 0.04 blended toward the base colour by metallic, alpha = roughness^2. p itself when t is p.type.
BsdfParams with_type(BsdfParams p, BsdfType t);
// Fits m.bsdf to m's per-hit inputs: a metallicRoughnessTexture may lower metallic anywhere in [0, factor] at a hit
// (apply_metallic_roughness_texel keeps the material's lobes), so a metallic-roughness BSDF with one carries every lobe
// of that range (a metallic factor of 1 alone has no diffuse or specular lobe). No effect otherwise.
void fit_bsdf_to_textures(Material& m);
// m.bsdf = make_bsdf(p), fitted to m's textures: what every editor of a loaded material calls (the viewer's panel,
// scene.json's material overrides), so that an edited glTF material shades as one loaded with those parameters.
void set_bsdf(Material& m, const BsdfParams& p);
// "diffuse", "glossy", "mirror", "glass", "metallic-roughness" (bsdf_type_name's words) <-> BsdfType; false for
// anything else.
bool parse_bsdf_type(const std::string& name, BsdfType& out);

}  // namespace pv
