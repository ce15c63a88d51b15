// core/scene/material_params.cpp: parameters <-> Bsdf (see material_params.h).
#include "core/scene/material_params.h"

namespace pv {

BsdfParams bsdf_params(const Bsdf& bsdf) {
    BsdfParams p;
    if (const auto* l = std::get_if<Lambertian>(&bsdf)) {
        p.type = BsdfType::Diffuse;
        p.base = l->albedo;
    } else if (const auto* g = std::get_if<Glossy>(&bsdf)) {
        p.type = BsdfType::Glossy;
        p.base = g->diffuse;
        p.specular = g->specular;
        p.roughness = g->alpha;
    } else if (const auto* m = std::get_if<Mirror>(&bsdf)) {
        p.type = BsdfType::Mirror;
        p.base = p.specular = m->reflectance;
    } else if (const auto* d = std::get_if<Dielectric>(&bsdf)) {
        p.type = BsdfType::Glass;
        p.ior = d->eta;
    } else if (const auto* mr = std::get_if<MetallicRoughness>(&bsdf)) {
        p.type = BsdfType::MetallicRoughness;
        p.base = mr->base_color;
        p.specular = mr->specular_color;
        p.roughness = mr->roughness;
        p.ior = mr->ior;
        p.metallic = mr->metallic;
        p.transmission = mr->transmission;
        p.specular_weight = mr->specular;
        p.thin_walled = mr->thin_walled;
        p.attenuation_color = mr->attenuation_color;
        p.attenuation_distance = mr->attenuation_distance;
        p.clearcoat = mr->clearcoat;
        p.clearcoat_roughness = mr->clearcoat_roughness;
        p.sheen_color = mr->sheen_color;
        p.sheen_roughness = mr->sheen_roughness;
    }
    return p;
}

Bsdf make_bsdf(const BsdfParams& p) {
    auto unit = [](vec3 c) {
        // NaN fails both comparisons of clamp; map it to 0 explicitly.
        return vec3(std::isfinite(c.x) ? glm::clamp(c.x, 0.f, 1.f) : 0.f,
                    std::isfinite(c.y) ? glm::clamp(c.y, 0.f, 1.f) : 0.f,
                    std::isfinite(c.z) ? glm::clamp(c.z, 0.f, 1.f) : 0.f);
    };
    switch (p.type) {
        case BsdfType::Glossy: {
            Glossy g;
            g.specular = unit(p.specular);
            g.diffuse = glm::min(unit(p.base), vec3(1.f) - g.specular);
            g.alpha = std::isfinite(p.roughness) ? glm::clamp(p.roughness, kMinAlpha, 1.f) : 1.f;
            return g;
        }
        case BsdfType::Mirror:
            return Mirror{unit(p.base)};
        case BsdfType::Glass:
            return Dielectric{std::isfinite(p.ior) && p.ior > 0.f ? p.ior : 1.5f};
        case BsdfType::MetallicRoughness: {
            MetallicRoughness m;  // prepare_metallic_roughness() clamps every field
            m.base_color = p.base;
            m.specular_color = p.specular;
            m.roughness = p.roughness;
            m.ior = p.ior;
            m.metallic = p.metallic;
            m.transmission = p.transmission;
            m.specular = p.specular_weight;
            m.thin_walled = p.thin_walled;
            m.attenuation_color = p.attenuation_color;
            m.attenuation_distance = p.attenuation_distance;
            m.clearcoat = p.clearcoat;
            m.clearcoat_roughness = p.clearcoat_roughness;
            m.sheen_color = p.sheen_color;
            m.sheen_roughness = p.sheen_roughness;
            prepare_metallic_roughness(m);
            return m;
        }
        case BsdfType::Diffuse:
            break;
    }
    return Lambertian{unit(p.base)};
}

BsdfParams with_type(BsdfParams p, BsdfType t) {
    if (t == p.type) return p;
    const BsdfParams d;  // the defaults
    if (t == BsdfType::MetallicRoughness) {
        BsdfParams q;
        q.type = t;
        q.base = p.type == BsdfType::Glass ? vec3(1.f) : p.base;
        q.specular = vec3(1.f);
        q.specular_weight = 1.f;
        q.ior = p.type == BsdfType::Glass ? p.ior : d.ior;
        q.metallic = p.type == BsdfType::Mirror ? 1.f : 0.f;
        q.transmission = p.type == BsdfType::Glass ? 1.f : 0.f;
        q.roughness = p.type == BsdfType::Glossy    ? std::sqrt(std::max(p.roughness, 0.f))
                      : p.type == BsdfType::Diffuse ? 1.f
                                                    : 0.f;
        return q;
    }
    if (p.type == BsdfType::MetallicRoughness && t == BsdfType::Glossy) {
        const float m = glm::clamp(p.metallic, 0.f, 1.f);
        BsdfParams q;
        q.type = t;
        q.specular = glm::mix(d.specular, p.base, m);
        q.base = p.base * (1.f - m);
        q.roughness = std::max(p.roughness * p.roughness, kMinAlpha);
        return q;
    }
    p.type = t;
    return p;
}

void fit_bsdf_to_textures(Material& m) {
    auto* mr = std::get_if<MetallicRoughness>(&m.bsdf);
    if (!mr || m.metallic_roughness_texture == kNoIndex || !(mr->metallic > 0.f)) return;
    MetallicRoughness any = *mr;
    any.metallic = 0.5f;
    prepare_metallic_roughness(any);
    mr->lobes = any.lobes;
    mr->delta_only = any.delta_only;
    mr->lambert_only = false;
}

void set_bsdf(Material& m, const BsdfParams& p) {
    m.bsdf = make_bsdf(p);
    fit_bsdf_to_textures(m);
}

bool parse_bsdf_type(const std::string& name, BsdfType& out) {
    static const char* const names[] = {"diffuse", "glossy", "mirror", "glass", "metallic-roughness"};
    for (int i = 0; i < 5; ++i)
        if (name == names[i]) {
            out = BsdfType(i);
            return true;
        }
    return false;
}

}  // namespace pv
