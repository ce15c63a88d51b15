// core/render/shading.h: what a material is at one hit, as the path tracer shades it: the normal map's shading normal
// and the BSDF with its per-hit inputs (base-colour texture, glTF COLOR_0 vertex colour, metallic-roughness texture)
// applied, for every caller that shades a hit (below the includes).
#pragma once

#include "core/render/normal_map.h"
#include "core/render/surface.h"
#include "core/scene/bsdf.h"
#include "core/scene/scene.h"

// The callers: the integrator, the AOV pass (core/denoise/aov.cpp: the denoisers' albedo and normal) and the sky
// guide's training walk (core/render/sky_guide.cpp) all go through these functions, so that the features and the guide
// see the surface the render shades.

namespace pv {

// A material's normal map applied to sf.ns at hit (prim, u, v), read at uv (the hit's set-0 uv), for a ray arriving
// from wo_world: the mapped normal, bent where a grazing view would reflect below the surface (a flat texel leaves
// sf.ns as it is). No effect for a material without a normal map.
inline void apply_normal_map(const Scene& s, const Material& mat, const Hit& hit, vec2 uv, vec3 wo_world,
                             SurfacePoint& sf) {
    if (mat.normal_texture == kNoIndex) return;
    const vec3 n =
        normal_mapped(s, hit.prim, hit.u, hit.v, sf, vec3(s.textures[mat.normal_texture].lookup(uv)), mat.normal_scale);
    if (n != sf.ns) sf.ns = valid_reflection_normal(sf.ng, wo_world, n);
}

// The radiance `mat` emits at hit (prim, u, v) (when it emits there: TraceableScene::emits): its emission times its
// emissive texture's RGB at that texture's uv (Scene::texcoord, the light set's rule), the emission alone without one.
inline vec3 emitted_at(const Scene& s, const Material& mat, uint32_t prim, float u, float v) {
    if (mat.emissive_texture == kNoIndex) return mat.emission;
    return mat.emission * vec3(s.textures[mat.emissive_texture].lookup(s.texcoord(prim, u, v, mat.emissive_uv)));
}

// What a hit's BSDF reads per hit besides the material's constant one.
struct HitTextures {
    const Texture* base_color = nullptr;   // the material's base-colour texture, read at uv
    const Texture* metal_rough = nullptr;  // a glTF metallicRoughnessTexture, read at uv
    vec2 uv{0.f};                          // set when one of the textures is
    bool has_color = false;                // the triangle has vertex colours (glTF COLOR_0): color multiplies
    vec3 color{1.f};
    // A material with clearcoat or sheen textures (Material::has_layer_textures), and the scene's textures.
    const Material* layers = nullptr;
    const Texture* textures = nullptr;
    bool per_hit() const { return base_color || metal_rough || has_color || layers; }
};

// The per-hit inputs of `mat` at `hit`; uv_of() gives the hit's uv (the scene's or a packed record's: the same bits),
// called only for a textured material. Only scenes with vertex colours test for them, only triangles with them pay.
template <class UvOf>
[[gnu::always_inline]] inline HitTextures hit_textures(const Scene& s, const Material& mat, const Hit& hit,
                                                       UvOf uv_of) {
    HitTextures t;
    t.base_color = mat.base_color_texture != kNoIndex ? &s.textures[mat.base_color_texture] : nullptr;
    t.metal_rough = mat.metallic_roughness_texture != kNoIndex ? &s.textures[mat.metallic_roughness_texture] : nullptr;
    t.has_color = !s.color_indices.empty() && s.color_indices[hit.prim].x != kNoIndex;
    if (t.has_color) [[unlikely]]
        t.color = s.color_at(hit.prim, hit.u, hit.v);
    if (mat.has_layer_textures()) [[unlikely]] {
        t.layers = &mat;
        t.textures = s.textures.data();
    }
    if (t.base_color || t.metal_rough || t.layers) t.uv = uv_of();
    return t;
}
inline HitTextures hit_textures(const Scene& s, const Material& mat, const Hit& hit) {
    return hit_textures(s, mat, hit, [&] { return s.uv_at(hit.prim, hit.u, hit.v); });
}

// Applies t to `bsdf` (a copy of the material's): the base colour texel `base_texel` (t.base_color's lookup at t.uv;
// the integrator's comes from prefetched texels), then the vertex colour, then the metallic-roughness texel, then the
// clearcoat and sheen texels.
inline void apply_hit_textures(Bsdf& bsdf, const HitTextures& t, vec4 base_texel) {
    if (t.base_color) set_base_color(bsdf, vec3(base_texel));
    if (t.has_color) multiply_base_color(bsdf, t.color);
    if (t.metal_rough)
        if (auto* mr = std::get_if<MetallicRoughness>(&bsdf)) {
            const vec4 m = t.metal_rough->lookup(t.uv);
            apply_metallic_roughness_texel(*mr, m.z, m.y);
        }
    if (t.layers) [[unlikely]]
        if (auto* mr = std::get_if<MetallicRoughness>(&bsdf)) {
            const Material& m = *t.layers;
            auto texel = [&](uint32_t i) { return i != kNoIndex ? t.textures[i].lookup(t.uv) : vec4(1.f); };
            if (m.clearcoat_texture != kNoIndex || m.clearcoat_roughness_texture != kNoIndex)
                apply_clearcoat_texel(*mr, texel(m.clearcoat_texture).x, texel(m.clearcoat_roughness_texture).y);
            if (m.sheen_color_texture != kNoIndex || m.sheen_roughness_texture != kNoIndex)
                apply_sheen_texel(*mr, vec3(texel(m.sheen_color_texture)), texel(m.sheen_roughness_texture).w);
        }
}

// The BSDF the path tracer shades `mat` with at a hit whose per-hit inputs are t.
inline Bsdf hit_bsdf(const Material& mat, const HitTextures& t) {
    Bsdf bsdf = mat.bsdf;
    if (t.per_hit()) apply_hit_textures(bsdf, t, t.base_color ? t.base_color->lookup(t.uv) : vec4(0.f));
    return bsdf;
}

}  // namespace pv
