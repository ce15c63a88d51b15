// core/load/gltf_materials.cpp: glTF materials (metallic-roughness, emission, alpha modes, KHR material extensions and
// texture transforms) and cameras, converted into pathview's Material and CameraDesc (see gltf_loader.h).
#include "core/image/image_io.h"
#include "core/load/gltf_internal.h"
#include "core/scene/material_params.h"

namespace pv::gltf_detail {
namespace {

// A glTF UvTransform (in glTF's uv space, v down) as pathview's uv space sees it (v up, as OBJ): flip, transform,
// flip back; F(T(F(uv))) with F(w) = (w.x, 1 - w.y).
UvTransform to_pathview_uv(const UvTransform& t) {
    UvTransform r = t;
    r.col0 = vec2(t.col0.x, -t.col0.y);
    r.col1 = vec2(-t.col1.x, t.col1.y);
    r.offset = vec2(t.col1.x + t.offset.x, 1.f - (t.col1.y + t.offset.y));
    return r;
}

// The largest index of refraction a material takes (scene files refuse more: core/load/scene_file.cpp).
constexpr float kMaxIor = 1e3f;

// The parameters of one glTF material, as the file gives them (the BSDF is built from them in one place).
struct GltfMaterial {
    vec4 base_color{1.f};
    float metallic = 1.f, roughness = 1.f;  // perceptual roughness
    float ior = 1.5f;
    double ior_above_bound = 0.0;  // KHR_materials_ior's value when above kMaxIor (then clamped to it)
    float specular = 1.f;
    vec3 specular_color{1.f};
    float transmission = 0.f;
    float thickness = 0.f;  // KHR_materials_volume: 0 is thin-walled
    vec3 attenuation_color{1.f};
    float attenuation_distance = std::numeric_limits<float>::infinity();
};

// The BSDF of a glTF material: core/scene/bsdf_pbr.h's MetallicRoughness, through make_bsdf (which clamps, and keeps
// only the lobes the parameters make non-zero).
Bsdf gltf_bsdf(const GltfMaterial& g) {
    BsdfParams p;
    p.type = BsdfType::MetallicRoughness;
    p.base = vec3(g.base_color);
    p.metallic = g.metallic;
    p.roughness = g.roughness;
    p.ior = g.ior;
    p.specular_weight = g.specular;
    p.specular = g.specular_color;
    p.transmission = g.transmission;
    p.thin_walled = !(g.thickness > 0.f);
    p.attenuation_color = g.attenuation_color;
    p.attenuation_distance = g.attenuation_distance;
    return make_bsdf(p);
}

}  // namespace

// ---- Materials ----

uint32_t Loader::image_texture_index(int image, TextureWrap ws, TextureWrap wt) {
    const auto key = std::make_tuple(image, ws, wt);
    if (auto it = image_texture.find(key); it != image_texture.end()) return it->second;
    const auto img = images.find(image);
    if (img == images.end()) return kNoIndex;
    scene->textures.push_back(img->second);
    scene->textures.back().set_wrap(ws, wt);
    const uint32_t id = uint32_t(scene->textures.size() - 1);
    image_texture[key] = id;
    return id;
}

// A glTF sampler's wrapS or wrapT (10497 REPEAT, 33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT) as a TextureWrap;
// any other value repeats, with a warning naming it.
TextureWrap Loader::wrap_mode(int gl, const std::string& at) {
    switch (gl) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT:
            return TextureWrap::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return TextureWrap::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return TextureWrap::MirroredRepeat;
        default:
            warn_once(at,
                      at + ": wrap mode " + std::to_string(gl) +
                          " is not one of 10497 (REPEAT), 33071 (CLAMP_TO_EDGE), 33648 (MIRRORED_REPEAT); REPEAT used");
            return TextureWrap::Repeat;
    }
}

// The decoded image a texture reference names (kNoIndex, with a warning, if none), with its sampler's wrap modes,
// and in `uv` its texture coordinate set and KHR_texture_transform (in glTF's uv space).
uint32_t Loader::texture_of(const tinygltf::TextureInfo& info, const std::string& at, UvTransform& uv) {
    uv = UvTransform{};
    if (info.index < 0) return kNoIndex;
    if (size_t(info.index) >= model.textures.size()) {
        warn_once(at, at + "/index: texture " + std::to_string(info.index) + " does not exist; flat colour used");
        return kNoIndex;
    }
    const tinygltf::Texture& texture = model.textures[size_t(info.index)];
    int source = texture.source;
    if (const tinygltf::Value* webp = extension(texture.extensions, "EXT_texture_webp")) {  // preferred when present
        const double d = value_number(*webp, "source", -1.0);
        if (d >= 0.0 && d < 2147483647.0) source = int(d);
    }
    TextureWrap ws = TextureWrap::Repeat, wt = TextureWrap::Repeat;  // no sampler: repeat (the specification)
    if (texture.sampler >= 0 && size_t(texture.sampler) < model.samplers.size()) {
        const tinygltf::Sampler& sm = model.samplers[size_t(texture.sampler)];
        const std::string s_at = ptr({"samplers", str(size_t(texture.sampler))});
        ws = wrap_mode(sm.wrapS, s_at + "/wrapS");
        wt = wrap_mode(sm.wrapT, s_at + "/wrapT");
    }
    const uint32_t id = source >= 0 ? image_texture_index(source, ws, wt) : kNoIndex;
    if (id == kNoIndex) {
        warn_once(at, at + ": texture " + std::to_string(info.index) +
                          " has no decodable image (see the image's warning); flat colour used");
        return kNoIndex;
    }
    uv.set = info.texCoord == 1 ? 1u : 0u;
    if (info.texCoord > 1) warn_once(at + "texcoord", at + "/texCoord: only TEXCOORD_0 and _1 are read; 0 used");
    if (const tinygltf::Value* t = extension(info.extensions, "KHR_texture_transform")) {
        double off[2] = {0, 0}, sc[2] = {1, 1};
        value_numbers(*t, "offset", off, 2);
        value_numbers(*t, "scale", sc, 2);
        const float r = finite_or(value_number(*t, "rotation", 0.0), 0.f);
        const float c = std::cos(r), sn = std::sin(r);
        // uv' = offset + R (scale * uv), R = [c s; -s c] (the extension's matrix: a counter-clockwise rotation of
        // the uvs in glTF's v-down space).
        uv.col0 = finite_or(sc[0], 1.f) * vec2(c, -sn);
        uv.col1 = finite_or(sc[1], 1.f) * vec2(sn, c);
        uv.offset = vec2(finite_or(off[0], 0.f), finite_or(off[1], 0.f));
        const double set = value_number(*t, "texCoord", -1.0);
        if (set == 0.0 || set == 1.0) uv.set = uint32_t(set);
    }
    return id;
}

namespace {

// The factors of a glTF material and of its KHR material extensions, clamped to their ranges.
GltfMaterial material_parameters(const tinygltf::Material& gm) {
    const auto& pbr = gm.pbrMetallicRoughness;
    GltfMaterial g;
    if (pbr.baseColorFactor.size() == 4)
        for (int c = 0; c < 4; ++c)
            g.base_color[c] = glm::clamp(finite_or(pbr.baseColorFactor[size_t(c)], 1.f), 0.f, 1.f);
    g.metallic = glm::clamp(finite_or(pbr.metallicFactor, 1.f), 0.f, 1.f);
    g.roughness = glm::clamp(finite_or(pbr.roughnessFactor, 1.f), 0.f, 1.f);
    if (const tinygltf::Value* e = extension(gm.extensions, "KHR_materials_ior")) {
        const double given = value_number(*e, "ior", 1.5);
        const float ior = finite_or(given, 1.5f);
        g.ior = ior >= 1.f ? ior : 1.5f;  // 0 (the extension's "no refraction" value) and below 1: default
        // Above the scene file's bound (1e3) the Fresnel terms lose all precision (1e8 made every sample NaN).
        if (g.ior > kMaxIor) g.ior_above_bound = given, g.ior = kMaxIor;
    }
    if (const tinygltf::Value* e = extension(gm.extensions, "KHR_materials_specular")) {
        g.specular = glm::clamp(finite_or(value_number(*e, "specularFactor", 1.0), 1.f), 0.f, 1.f);
        double sc[3];
        if (value_numbers(*e, "specularColorFactor", sc, 3))
            g.specular_color =
                glm::max(vec3(finite_or(sc[0], 1.f), finite_or(sc[1], 1.f), finite_or(sc[2], 1.f)), vec3(0.f));
    }
    if (const tinygltf::Value* e = extension(gm.extensions, "KHR_materials_transmission"))
        g.transmission = glm::clamp(finite_or(value_number(*e, "transmissionFactor", 0.0), 0.f), 0.f, 1.f);
    if (const tinygltf::Value* e = extension(gm.extensions, "KHR_materials_volume")) {
        g.thickness = std::max(finite_or(value_number(*e, "thicknessFactor", 0.0), 0.f), 0.f);
        double ac[3];
        if (value_numbers(*e, "attenuationColor", ac, 3))
            g.attenuation_color = glm::clamp(vec3(finite_or(ac[0], 1.f), finite_or(ac[1], 1.f), finite_or(ac[2], 1.f)),
                                             vec3(0.f), vec3(1.f));
        const float d = finite_or(value_number(*e, "attenuationDistance", 0.0), 0.f);
        if (d > 0.f) g.attenuation_distance = d;
    }
    return g;
}

// A texture of linear data (metallic-roughness, normals) as its texels are stored in the file: the decoder's sRGB
// decoding undone, in a copy of its own with the same wrap modes; one copy per source texture (`copies`), shared by
// the materials that use it.
uint32_t linear_copy(Scene& s, std::map<uint32_t, uint32_t>& copies, uint32_t src_index) {
    if (const auto it = copies.find(src_index); it != copies.end()) return it->second;
    const Texture& src = s.textures[src_index];
    std::vector<vec4> texels = src.texels();
    for (vec4& t : texels) t = vec4(linear_to_srgb(t.x), linear_to_srgb(t.y), linear_to_srgb(t.z), t.w);
    const TextureWrap ws = src.wrap_s(), wt = src.wrap_t();  // src moves when textures grows
    s.textures.emplace_back(src.width(), src.height(), std::move(texels));
    s.textures.back().set_wrap(ws, wt);
    const uint32_t id = uint32_t(s.textures.size() - 1);
    copies.emplace(src_index, id);
    return id;
}

// What the base colour texture and its transform (buv) are: where a material reads them.
struct BaseColor {
    uint32_t texture = kNoIndex;
    UvTransform uv;
    // The uv transform other textures must have to be read at the mesh's uvs (which carry the base colour's).
    UvTransform shared_uv() const { return texture != kNoIndex ? uv : UvTransform{}; }
};

// Base colour: the factor multiplies the texture (baked into a texture of its own when it is not white, since
// Material::base_color_texture replaces the colour); alphaMode decides the cut-out.
BaseColor set_base_color(Loader& L, const tinygltf::Material& gm, const GltfMaterial& g, const std::string& at,
                         Material& m) {
    Scene& s = *L.scene;
    BaseColor base;
    base.texture =
        L.texture_of(gm.pbrMetallicRoughness.baseColorTexture, at + "/pbrMetallicRoughness/baseColorTexture", base.uv);
    const bool mask = gm.alphaMode == "MASK", blend = gm.alphaMode == "BLEND";
    const float cutoff = finite_or(gm.alphaCutoff, 0.5f);
    if (base.texture != kNoIndex) {
        const bool white = vec3(g.base_color) == vec3(1.f);
        const bool alpha_used = mask || (blend && (g.base_color.w < 1.f || s.textures[base.texture].has_alpha()));
        if (white && !alpha_used) {
            m.base_color_texture = base.texture;
        } else {
            const Texture& src = s.textures[base.texture];
            std::vector<vec4> texels = src.texels();
            for (vec4& t : texels) {
                t = vec4(vec3(t) * vec3(g.base_color), t.w * g.base_color.w);
                if (mask) t.w = t.w >= cutoff ? 1.f : 0.f;
            }
            const TextureWrap ws = src.wrap_s(), wt = src.wrap_t();  // src moves when textures grows
            s.textures.emplace_back(src.width(), src.height(), std::move(texels));
            s.textures.back().set_wrap(ws, wt);
            m.base_color_texture = uint32_t(s.textures.size() - 1);
            if (alpha_used) m.alpha_texture = m.base_color_texture;
        }
    } else if ((mask && g.base_color.w < cutoff) || (blend && g.base_color.w < 1.f)) {
        // A constant opacity: a 1x1 texture of it (MASK below the cut-off: the surface is not there).
        const float a = mask ? 0.f : g.base_color.w;
        s.textures.emplace_back(1, 1, std::vector<vec4>{vec4(vec3(g.base_color), a)});
        m.alpha_texture = uint32_t(s.textures.size() - 1);
    }
    return base;
}

// metallicRoughnessTexture and normalTexture (linear data: linear_copy), read at the mesh's uvs, which carry the base
// colour's transform: each used where its own transform and texCoord are the same. m.bsdf is set.
void set_linear_textures(Loader& L, const tinygltf::Material& gm, const std::string& at, const BaseColor& base,
                         std::map<uint32_t, uint32_t>& copies, Material& m) {
    UvTransform muv;
    const std::string mr_at = at + "/pbrMetallicRoughness/metallicRoughnessTexture";
    const uint32_t mr_tex = L.texture_of(gm.pbrMetallicRoughness.metallicRoughnessTexture, mr_at, muv);
    if (mr_tex != kNoIndex && std::holds_alternative<MetallicRoughness>(m.bsdf)) {
        if (!(muv == base.shared_uv())) {
            L.warn_once(mr_at, mr_at +
                                   ": a texture transform or texCoord other than the base colour's is not "
                                   "supported; the metallic and roughness factors are used");
        } else {
            m.metallic_roughness_texture = linear_copy(*L.scene, copies, mr_tex);
            fit_bsdf_to_textures(m);  // the texel may lower metallic: every lobe of [0, factor]
        }
    }
    if (gm.normalTexture.index >= 0) {
        const std::string n_at = at + "/normalTexture";
        tinygltf::TextureInfo info;
        info.index = gm.normalTexture.index;
        info.texCoord = gm.normalTexture.texCoord;
        info.extensions = gm.normalTexture.extensions;
        UvTransform nuv;
        const uint32_t n_tex = L.texture_of(info, n_at, nuv);
        if (n_tex != kNoIndex) {
            if (!(nuv == base.shared_uv())) {
                L.warn_once(n_at, n_at +
                                      ": a texture transform or texCoord other than the base colour's is not "
                                      "supported; the normal map is not used");
            } else {
                m.normal_texture = linear_copy(*L.scene, copies, n_tex);
                const float sc = finite_or(gm.normalTexture.scale, 1.f);
                m.normal_scale = sc;
            }
        }
    }
}

// Emission: emissiveFactor x KHR_materials_emissive_strength (x emissiveTexture).
void set_emission(Loader& L, const tinygltf::Material& gm, const std::string& at, const BaseColor& base, Material& m) {
    vec3 e(0.f);
    if (gm.emissiveFactor.size() == 3)
        e = glm::max(vec3(finite_or(gm.emissiveFactor[0], 0.f), finite_or(gm.emissiveFactor[1], 0.f),
                          finite_or(gm.emissiveFactor[2], 0.f)),
                     vec3(0.f));
    if (const tinygltf::Value* x = extension(gm.extensions, "KHR_materials_emissive_strength"))
        e *= std::max(finite_or(value_number(*x, "emissiveStrength", 1.0), 1.f), 0.f);
    m.emission = is_finite(e) ? e : vec3(0.f);
    if (!m.has_emission()) return;
    UvTransform euv;
    m.emissive_texture = L.texture_of(gm.emissiveTexture, at + "/emissiveTexture", euv);
    if (m.emissive_texture == kNoIndex) return;
    // Set 0 holds the base colour texture's uvs (their transform applied); set 1 holds TEXCOORD_1 as is.
    const uint32_t base_tex = base.texture;
    const UvTransform& buv = base.uv;
    if (euv == buv && base_tex != kNoIndex) {
        m.emissive_uv = UvTransform{};
    } else if (euv.set == 1 || base_tex == kNoIndex || buv.is_identity()) {
        m.emissive_uv = to_pathview_uv(euv);
    } else {
        L.warn_once(at + "euv", at + "/emissiveTexture: its uv transform differs from the base colour "
                                     "texture's on TEXCOORD_0; the base colour's is used");
        m.emissive_uv = UvTransform{};
    }
}

}  // namespace

// Each glTF material in turn: its factors, base colour (and cut-out), BSDF, linear-data textures, emission.
void Loader::convert_materials() {
    base_uv.assign(model.materials.size(), UvTransform{});
    std::map<uint32_t, uint32_t> linear_copies;
    for (size_t mi = 0; mi < model.materials.size(); ++mi) {
        const tinygltf::Material& gm = model.materials[mi];
        const std::string at = ptr({"materials", str(mi)});
        const GltfMaterial g = material_parameters(gm);
        if (g.ior_above_bound > 0.0)
            warn_once(at + "/ior", at + "/extensions/KHR_materials_ior/ior: " + std::to_string(g.ior_above_bound) +
                                       " is above 1000 (the bound scene files apply); clamped to 1000");
        Material m;
        m.name = gm.name.empty() ? "material " + str(mi) : gm.name;
        const BaseColor base = set_base_color(*this, gm, g, at, m);
        if (base.texture != kNoIndex) base_uv[mi] = base.uv;
        m.bsdf = gltf_bsdf(g);
        set_linear_textures(*this, gm, at, base, linear_copies, m);
        set_emission(*this, gm, at, base, m);
        m.two_sided_emission = gm.doubleSided;
        scene->materials.push_back(std::move(m));
    }
}

uint32_t Loader::material_index(int gltf_material, const std::string& at) {
    if (gltf_material >= 0 && size_t(gltf_material) < model.materials.size()) return uint32_t(gltf_material);
    if (gltf_material >= 0)
        warn_once("bad material",
                  at + ": material " + std::to_string(gltf_material) + " does not exist; the default material is used");
    if (default_material == kNoIndex) {
        // glTF's default material: white, metallic 1, roughness 1 (the specification's defaults). pathview uses
        // its own default grey diffuse instead, as for an OBJ face without a material.
        default_material = uint32_t(scene->materials.size());
        scene->materials.push_back(Material{});
    }
    return default_material;
}

// ---- Cameras ----

void Loader::convert_cameras() {
    Scene& s = *scene;
    vec3 lo, hi;
    s.bounds(lo, hi);
    const vec3 centre = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    std::set<std::string> names;
    bool first = true;
    for (size_t i = 0; i < cameras.size(); ++i) {
        const CameraInstance& ci = cameras[i];
        const tinygltf::Camera& c = model.cameras[size_t(ci.camera)];
        if (c.type != "perspective") {
            warn_once("ortho", ptr({"cameras", str(size_t(ci.camera))}) + ": camera type '" + c.type +
                                   "' is not supported (perspective only); camera ignored");
            continue;
        }
        const vec3 eye = vec3(ci.world * dvec4(0.0, 0.0, 0.0, 1.0));
        const dvec3 fwd = dmat3(ci.world) * dvec3(0.0, 0.0, -1.0);
        const dvec3 up = dmat3(ci.world) * dvec3(0.0, 1.0, 0.0);
        if (!is_finite(eye) || !(glm::length(fwd) > 0.0) || !(glm::length(up) > 0.0)) {
            warn_once("camera transform",
                      ptr({"nodes", str(size_t(ci.node))}) + ": the camera's transform is degenerate; camera ignored");
            continue;
        }
        CameraDesc d;
        d.eye = eye;
        const vec3 f = vec3(glm::normalize(fwd));
        // The target: the scene's centre projected on the view axis (the viewer orbits about it), at least a
        // hundredth of the scene's size ahead.
        d.target = eye + f * std::max(glm::dot(centre - eye, f), 0.01f * radius);
        d.up = vec3(glm::normalize(up));
        const double yfov = c.perspective.yfov;
        d.vfov_deg = std::isfinite(yfov) && yfov > 0.0 ? glm::clamp(float(glm::degrees(yfov)), 0.01f, 179.f) : 40.f;
        std::string name = !c.name.empty()                              ? c.name
                           : !model.nodes[size_t(ci.node)].name.empty() ? model.nodes[size_t(ci.node)].name
                                                                        : "camera " + str(size_t(ci.camera));
        for (int k = 2; !names.insert(name).second; ++k) name = name + " (" + std::to_string(k) + ")";
        s.bookmarks.push_back(Scene::Bookmark{name, d});
        if (first) {
            s.camera = d;
            s.has_camera = true;
            first = false;
        }
    }
}

}  // namespace pv::gltf_detail
