// core/partial/scene_hash.cpp: the scene identity hash (see scene_hash.h).
#include "core/partial/scene_hash.h"

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <type_traits>
#include <variant>

#include "core/sampling/rng.h"

namespace pv {
namespace {

// Word-at-a-time content hash (SplitMix64 mixing of each 8-byte word, core/sampling/rng.h).
class Hasher {
public:
    void bytes(const void* data, size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (; n >= 8; n -= 8, p += 8) {
            uint64_t w;
            std::memcpy(&w, p, 8);
            m_h = hash_combine(m_h, w);
        }
        uint64_t tail = 0;
        std::memcpy(&tail, p, n);
        m_h = hash_combine(m_h, tail ^ (uint64_t(n) << 56));
    }
    template <class T>
    void value(const T& v) {
        bytes(&v, sizeof v);
    }
    template <class T>
    void vector(const std::vector<T>& v) {
        value(uint64_t(v.size()));
        if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
    }
    void string(const std::string& s) {
        value(uint64_t(s.size()));
        bytes(s.data(), s.size());
    }
    uint64_t get() const { return m_h; }

private:
    uint64_t m_h = 0x7061727469616cull;
};

void hash_material(Hasher& h, const Material& m) {
    h.string(m.name);
    h.value(uint64_t(m.bsdf.index()));
    std::visit(
        [&](const auto& b) {
            using T = std::decay_t<decltype(b)>;
            if constexpr (std::is_same_v<T, Lambertian>) h.value(b.albedo);
            if constexpr (std::is_same_v<T, Mirror>) h.value(b.reflectance);
            if constexpr (std::is_same_v<T, Dielectric>) h.value(b.eta);
            if constexpr (std::is_same_v<T, Glossy>) {
                h.value(b.diffuse);
                h.value(b.specular);
                h.value(b.alpha);
            }
            if constexpr (std::is_same_v<T, MetallicRoughness>) {  // a new type: OBJ hashes are unchanged
                h.value(b.base_color);
                h.value(b.metallic);
                h.value(b.roughness);
                h.value(b.ior);
                h.value(b.specular);
                h.value(b.specular_color);
                h.value(b.transmission);
                h.value(uint8_t(b.thin_walled));
                h.value(b.attenuation_color);
                h.value(b.attenuation_distance);
                if (b.layered()) {  // clearcoat and sheen: unlayered materials hash as before
                    h.value(b.clearcoat);
                    h.value(b.clearcoat_roughness);
                    h.value(b.sheen_color);
                    h.value(b.sheen_roughness);
                }
            }
        },
        m.bsdf);
    h.value(m.emission);
    h.value(uint8_t(m.two_sided_emission));
    h.value(m.base_color_texture);
    h.value(m.alpha_texture);
    if (m.metallic_roughness_texture != kNoIndex) h.value(m.metallic_roughness_texture);  // glTF only
    if (m.normal_texture != kNoIndex) {                                                   // glTF only
        h.value(m.normal_texture);
        h.value(m.normal_scale);
    }
    if (m.has_layer_textures()) {  // glTF clearcoat and sheen textures only
        h.value(m.clearcoat_texture);
        h.value(m.clearcoat_roughness_texture);
        h.value(m.sheen_color_texture);
        h.value(m.sheen_roughness_texture);
    }
    if (m.emissive_texture != kNoIndex || !m.emissive_uv.is_identity()) {  // glTF only: OBJ hashes as before
        h.value(m.emissive_texture);
        h.value(m.emissive_uv.col0);
        h.value(m.emissive_uv.col1);
        h.value(m.emissive_uv.offset);
        h.value(m.emissive_uv.set);
    }
    if (!m.medium.empty()) {  // an interior medium: materials without one hash as before
        h.value(m.medium.sigma_a);
        h.value(m.medium.sigma_s);
        h.value(m.medium.g);
    }
}

}  // namespace

uint64_t scene_hash(const Scene& scene, const std::vector<Material>& materials, const EnvironmentSettings& env,
                    const HomogeneousMedium& fog) {
    Hasher h;
    h.vector(scene.positions);
    h.vector(scene.triangles);
    h.vector(scene.normals);
    h.vector(scene.normal_indices);
    h.vector(scene.uvs);
    h.vector(scene.uv_indices);
    h.vector(scene.material_ids);
    if (!scene.colors.empty()) {  // vertex colours (glTF COLOR_0) only when present: other scenes hash as before
        h.vector(scene.colors);
        h.vector(scene.color_indices);
    }
    if (!scene.tangents.empty()) {  // glTF TANGENT only when present
        h.vector(scene.tangents);
        h.vector(scene.tangent_indices);
    }
    if (!scene.uvs1.empty() || !scene.punctual_lights.empty()) {  // glTF only: OBJ scenes hash as before
        h.vector(scene.uvs1);
        h.vector(scene.uv1_indices);
        h.value(uint64_t(scene.punctual_lights.size()));
        for (const PunctualLight& l : scene.punctual_lights) {
            h.value(uint8_t(l.type));
            h.value(l.position);
            h.value(l.direction);
            h.value(l.intensity);
            h.value(l.range);
            h.value(l.inner_cone_rad);
            h.value(l.outer_cone_rad);
        }
    }
    h.value(uint64_t(materials.size()));
    for (const Material& m : materials) hash_material(h, m);
    h.value(uint64_t(scene.textures.size()));
    for (const Texture& t : scene.textures) {
        h.value(t.width());
        h.value(t.height());
        h.vector(t.texels());
        if (t.wrap_s() != TextureWrap::Repeat || t.wrap_t() != TextureWrap::Repeat) {  // glTF only: OBJ as before
            h.value(uint8_t(t.wrap_s()));
            h.value(uint8_t(t.wrap_t()));
        }
    }
    h.value(scene.environment_map);
    h.value(env.background);
    h.value(env.rotation_deg);
    h.value(env.strength);
    h.value(env.sun_direction);
    h.value(env.sun_angular_radius_deg);
    h.value(env.sun_irradiance);
    if (!fog.empty()) {  // the global medium only when present: scenes without one hash as before
        h.value(fog.sigma_a);
        h.value(fog.sigma_s);
        h.value(fog.g);
    }
    return h.get();
}

std::string hash_hex(uint64_t v) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
    return buf;
}

}  // namespace pv
