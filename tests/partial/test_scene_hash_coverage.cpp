// tests/partial/test_scene_hash_coverage.cpp: the scene hash (core/partial/scene_hash.cpp) lists the fields of
// Scene, Material, the BSDFs, the environment, punctual lights and the medium by hand. Here each struct's fields are
// listed again, each either with a change that must change the hash or with the reason it is not hashed; the list's
// length is compared with the struct's field count (counted independently, support/field_count.h), so a field added
// to one of these structs fails here until it is hashed (or the reason it need not be is written down).
// Test kinds: unit
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "core/partial/scene_hash.h"
#include "core/scene/bsdf_pbr.h"
#include "core/scene/scene.h"
#include "support/field_count.h"

namespace pv {
namespace {

using test::field_count;

// What a hash is taken of: a one-triangle scene with vertex colours and tangents, a metallic-roughness material with
// its textures (so the glTF-only fields, hashed only when present, are met), a glossy one, a punctual light and a
// fog, all changeable.
struct Input {
    Scene scene;
    std::vector<Material> materials;
    EnvironmentSettings env;
    Input() {
        scene.positions = {vec3(0.f), vec3(1.f, 0.f, 0.f), vec3(0.f, 1.f, 0.f)};
        scene.triangles = {uvec3(0, 1, 2)};
        scene.material_ids = {0};
        scene.colors = {vec3(1.f)};
        scene.color_indices = {uvec3(0)};
        scene.tangents = {vec4(1.f)};
        scene.tangent_indices = {uvec3(0)};
        scene.punctual_lights.resize(1);
        scene.fog.sigma_s = vec3(0.1f);
        Material m;
        MetallicRoughness mr;  // with a coat and a sheen, whose parameters are hashed only when present
        mr.clearcoat = 0.5f;
        mr.sheen_color = vec3(0.5f);
        m.bsdf = make_metallic_roughness(mr);
        m.clearcoat_texture = 0;
        m.metallic_roughness_texture = 0;
        m.normal_texture = 0;
        m.emissive_texture = 0;
        Material g;
        g.bsdf = Glossy{};
        materials = {m, g};
    }
    uint64_t hash() const { return scene_hash(scene, materials, env); }
    MetallicRoughness& mr() { return std::get<MetallicRoughness>(materials[0].bsdf); }
    Glossy& glossy() { return std::get<Glossy>(materials[1].bsdf); }
};

struct Field {
    const char* name;
    std::function<void(Input&)> change;  // empty: not hashed, for `why`
    const char* why = "";
};

void expect_coverage(const char* type, size_t count, const std::vector<Field>& fields) {
    EXPECT_EQ(fields.size(), count) << type << " has " << count << " fields and this list " << fields.size()
                                    << ": hash the new field in core/partial/scene_hash.cpp and list it here";
    const uint64_t base = Input().hash();
    for (const Field& f : fields) {
        if (!f.change) {
            EXPECT_STRNE(f.why, "") << type << "::" << f.name;
            continue;
        }
        Input in;
        f.change(in);
        EXPECT_NE(in.hash(), base) << type << "::" << f.name << " is not hashed";
    }
}

const char* const kNotContent = "not the scene's content: a message, a statistic or a loader's note";

TEST(SceneHashCoverage, EveryFieldOfSceneIsHashedOrSaysWhyNot) {
    auto add3 = [](auto& v) { v.push_back(typename std::decay_t<decltype(v)>::value_type(0.5f)); };
    auto addi = [](auto& v) { v.push_back(typename std::decay_t<decltype(v)>::value_type(0)); };
    expect_coverage("Scene", field_count<Scene>(),
                    {{"positions", [&](Input& i) { add3(i.scene.positions); }},
                     {"triangles", [&](Input& i) { addi(i.scene.triangles); }},
                     {"normals", [&](Input& i) { add3(i.scene.normals); }},
                     {"normal_indices", [&](Input& i) { addi(i.scene.normal_indices); }},
                     {"uvs", [&](Input& i) { add3(i.scene.uvs); }},
                     {"uv_indices", [&](Input& i) { addi(i.scene.uv_indices); }},
                     {"uvs1", [&](Input& i) { add3(i.scene.uvs1); }},
                     {"uv1_indices", [&](Input& i) { addi(i.scene.uv1_indices); }},
                     {"colors", [&](Input& i) { add3(i.scene.colors); }},
                     {"color_indices", [&](Input& i) { i.scene.color_indices[0] = uvec3(1); }},
                     {"tangents", [&](Input& i) { add3(i.scene.tangents); }},
                     {"tangent_indices", [&](Input& i) { i.scene.tangent_indices[0] = uvec3(1); }},
                     {"material_ids", [&](Input& i) { i.scene.material_ids[0] = 1; }},
                     {"materials", {}, "hashed as passed: the live materials (a viewer edit), not the loaded ones"},
                     {"textures", [&](Input& i) { i.scene.textures.emplace_back(); }},
                     {"camera", {}, "the camera is part of the render's identity beside the scene hash"},
                     {"environment_map", [&](Input& i) { i.scene.environment_map = 0; }},
                     {"environment", {}, "hashed as passed: the live environment (flags and viewer edits)"},
                     {"portals", {}, "a sampling aid: the converged image does not depend on it"},
                     {"punctual_lights", [&](Input& i) { i.scene.punctual_lights.emplace_back(); }},
                     {"fog", [&](Input& i) { i.scene.fog.g = 0.5f; }},
                     {"has_camera", {}, "whether the file had a camera: the camera itself is in the identity"},
                     {"bookmarks", {}, "saved cameras, not the scene"},
                     {"source", {}, kNotContent},
                     {"stats", {}, kNotContent},
                     {"warnings", {}, kNotContent},
                     {"default_sky_warning", {}, kNotContent}});
}

TEST(SceneHashCoverage, EveryFieldOfMaterialIsHashed) {
    expect_coverage(
        "Material", field_count<Material>(),
        {{"name", [](Input& i) { i.materials[0].name = "other"; }},
         {"bsdf", [](Input& i) { i.materials[0].bsdf = Lambertian{}; }},
         {"emission", [](Input& i) { i.materials[0].emission = vec3(1.f); }},
         {"two_sided_emission", [](Input& i) { i.materials[0].two_sided_emission = true; }},
         {"base_color_texture", [](Input& i) { i.materials[0].base_color_texture = 0; }},
         {"alpha_texture", [](Input& i) { i.materials[0].alpha_texture = 0; }},
         {"metallic_roughness_texture", [](Input& i) { i.materials[0].metallic_roughness_texture = 1; }},
         {"emissive_texture", [](Input& i) { i.materials[0].emissive_texture = 1; }},
         {"emissive_uv", [](Input& i) { i.materials[0].emissive_uv.offset = vec2(0.5f); }},
         {"normal_texture", [](Input& i) { i.materials[0].normal_texture = 1; }},
         {"normal_scale", [](Input& i) { i.materials[0].normal_scale = 0.5f; }},
         {"medium", [](Input& i) { i.materials[0].medium.sigma_s = vec3(0.5f); }},
         {"clearcoat_texture", [](Input& i) { i.materials[0].clearcoat_texture = 1; }},
         {"clearcoat_roughness_texture", [](Input& i) { i.materials[0].clearcoat_roughness_texture = 1; }},
         {"sheen_color_texture", [](Input& i) { i.materials[0].sheen_color_texture = 1; }},
         {"sheen_roughness_texture", [](Input& i) { i.materials[0].sheen_roughness_texture = 1; }},
         {"light_group", {}, "which group a light's emission is credited to: no pixel of the image changes"}});
}

TEST(SceneHashCoverage, EveryParameterOfTheBsdfsIsHashed) {
    const char* derived = "derived from the parameters by prepare_metallic_roughness";
    expect_coverage("MetallicRoughness", field_count<MetallicRoughness>(),
                    {{"base_color", [](Input& i) { i.mr().base_color = vec3(0.5f); }},
                     {"metallic", [](Input& i) { i.mr().metallic = 0.5f; }},
                     {"roughness", [](Input& i) { i.mr().roughness = 0.5f; }},
                     {"ior", [](Input& i) { i.mr().ior = 1.3f; }},
                     {"specular", [](Input& i) { i.mr().specular = 0.5f; }},
                     {"specular_color", [](Input& i) { i.mr().specular_color = vec3(0.5f); }},
                     {"transmission", [](Input& i) { i.mr().transmission = 0.5f; }},
                     {"thin_walled", [](Input& i) { i.mr().thin_walled = false; }},
                     {"attenuation_color", [](Input& i) { i.mr().attenuation_color = vec3(0.5f); }},
                     {"attenuation_distance", [](Input& i) { i.mr().attenuation_distance = 2.f; }},
                     {"clearcoat", [](Input& i) { i.mr().clearcoat = 0.25f; }},
                     {"clearcoat_roughness", [](Input& i) { i.mr().clearcoat_roughness = 0.5f; }},
                     {"sheen_color", [](Input& i) { i.mr().sheen_color = vec3(0.25f); }},
                     {"sheen_roughness", [](Input& i) { i.mr().sheen_roughness = 0.5f; }},
                     {"coat_alpha", {}, derived},
                     {"sheen_alpha", {}, derived},
                     {"alpha", {}, derived},
                     {"f0", {}, derived},
                     {"spec_f0", {}, derived},
                     {"lobes", {}, derived},
                     {"delta_only", {}, derived},
                     {"lambert_only", {}, derived},
                     {"sigma", {}, derived}});
    expect_coverage("Glossy", field_count<Glossy>(),
                    {{"diffuse", [](Input& i) { i.glossy().diffuse = vec3(0.5f); }},
                     {"specular", [](Input& i) { i.glossy().specular = vec3(0.5f); }},
                     {"alpha", [](Input& i) { i.glossy().alpha = 0.5f; }}});
    expect_coverage("Lambertian", field_count<Lambertian>(),
                    {{"albedo", [](Input& i) { i.materials[1].bsdf = Lambertian{vec3(0.5f)}; }}});
    expect_coverage("Mirror", field_count<Mirror>(),
                    {{"reflectance", [](Input& i) { i.materials[1].bsdf = Mirror{vec3(0.5f)}; }}});
    expect_coverage("Dielectric", field_count<Dielectric>(),
                    {{"eta", [](Input& i) { i.materials[1].bsdf = Dielectric{1.3f}; }}});
}

TEST(SceneHashCoverage, EveryFieldOfLightsEnvironmentAndFogIsHashed) {
    expect_coverage("EnvironmentSettings", field_count<EnvironmentSettings>(),
                    {{"background", [](Input& i) { i.env.background = vec3(0.5f); }},
                     {"rotation_deg", [](Input& i) { i.env.rotation_deg = 10.f; }},
                     {"strength", [](Input& i) { i.env.strength = 2.f; }},
                     {"sun_direction", [](Input& i) { i.env.sun_direction = vec3(1.f, 0.f, 0.f); }},
                     {"sun_angular_radius_deg", [](Input& i) { i.env.sun_angular_radius_deg = 1.f; }},
                     {"sun_irradiance", [](Input& i) { i.env.sun_irradiance = vec3(1.f); }}});
    expect_coverage("PunctualLight", field_count<PunctualLight>(),
                    {{"type", [](Input& i) { i.scene.punctual_lights[0].type = PunctualLight::Type::Spot; }},
                     {"position", [](Input& i) { i.scene.punctual_lights[0].position = vec3(1.f); }},
                     {"direction", [](Input& i) { i.scene.punctual_lights[0].direction = vec3(1.f, 0.f, 0.f); }},
                     {"intensity", [](Input& i) { i.scene.punctual_lights[0].intensity = vec3(2.f); }},
                     {"range", [](Input& i) { i.scene.punctual_lights[0].range = 2.f; }},
                     {"inner_cone_rad", [](Input& i) { i.scene.punctual_lights[0].inner_cone_rad = 0.1f; }},
                     {"outer_cone_rad", [](Input& i) { i.scene.punctual_lights[0].outer_cone_rad = 0.2f; }},
                     {"name", {}, "a label for messages and the panel"}});
    expect_coverage("HomogeneousMedium", field_count<HomogeneousMedium>(),
                    {{"sigma_a", [](Input& i) { i.scene.fog.sigma_a = vec3(0.5f); }},
                     {"sigma_s", [](Input& i) { i.scene.fog.sigma_s = vec3(0.5f); }},
                     {"g", [](Input& i) { i.scene.fog.g = 0.3f; }}});
}

}  // namespace
}  // namespace pv
