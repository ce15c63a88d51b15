// tests/scene/test_material_params.cpp: the one parameters <-> Bsdf conversion (core/scene/material_params.h) keeps
// core/scene/bsdf.h's promises for any input, and round-trips what it accepts.
// Test kinds: unit
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>

#include "core/load/scene_file.h"
#include "core/partial/scene_hash.h"
#include "core/render/shading.h"
#include "core/scene/material_params.h"

namespace pv {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

}  // namespace

TEST(MaterialParams, GlossyKeepsDiffusePlusSpecularAtMostOne) {
    BsdfParams p;
    p.type = BsdfType::Glossy;
    p.base = vec3(0.9f, 2.f, -1.f);
    p.specular = vec3(0.5f, 0.3f, 1.5f);
    p.roughness = 5.f;
    const Glossy g = std::get<Glossy>(make_bsdf(p));
    for (int c = 0; c < 3; ++c) {
        EXPECT_GE(g.diffuse[c], 0.f);
        EXPECT_GE(g.specular[c], 0.f);
        EXPECT_LE(g.diffuse[c] + g.specular[c], 1.f);
    }
    EXPECT_EQ(g.specular, vec3(0.5f, 0.3f, 1.f));
    EXPECT_EQ(g.diffuse, vec3(0.5f, 0.7f, 0.f));
    EXPECT_EQ(g.alpha, 1.f);
    p.roughness = 0.f;
    EXPECT_EQ(std::get<Glossy>(make_bsdf(p)).alpha, kMinAlpha);
}

TEST(MaterialParams, NonFiniteInputsGiveValidBsdfs) {
    BsdfParams p;
    p.base = vec3(kNaN, kInf, -kInf);
    p.specular = vec3(kNaN);
    p.roughness = kNaN;
    p.ior = kNaN;
    p.metallic = p.transmission = p.specular_weight = p.attenuation_distance = kNaN;
    for (BsdfType t :
         {BsdfType::Diffuse, BsdfType::Glossy, BsdfType::Mirror, BsdfType::Glass, BsdfType::MetallicRoughness}) {
        p.type = t;
        const BsdfParams back = bsdf_params(make_bsdf(p));
        EXPECT_EQ(back.type, t);
        EXPECT_TRUE(is_finite(back.base) && is_finite(back.specular));
        EXPECT_TRUE(std::isfinite(back.roughness) && std::isfinite(back.ior) && back.ior > 0.f);
        EXPECT_TRUE(std::isfinite(back.metallic) && std::isfinite(back.transmission) &&
                    std::isfinite(back.specular_weight) && back.attenuation_distance > 0.f);
        for (int c = 0; c < 3; ++c) EXPECT_LE(back.base[c] + (t == BsdfType::Glossy ? back.specular[c] : 0.f), 1.f);
    }
}

TEST(MaterialParams, RoundTripsValidParameters) {
    for (BsdfType t :
         {BsdfType::Diffuse, BsdfType::Glossy, BsdfType::Mirror, BsdfType::Glass, BsdfType::MetallicRoughness}) {
        BsdfParams p;
        p.type = t;
        p.base = vec3(0.25f, 0.5f, 0.125f);
        p.specular = t == BsdfType::Mirror ? p.base : vec3(0.5f, 0.25f, 0.75f);
        p.roughness = 0.3f;
        p.ior = 1.33f;
        p.metallic = 0.375f;
        p.transmission = 0.625f;
        p.specular_weight = 0.75f;
        p.thin_walled = false;
        p.attenuation_color = vec3(0.5f, 0.75f, 1.f);
        p.attenuation_distance = 2.f;
        const Bsdf b = make_bsdf(p);
        static const char* const kNames[] = {"diffuse", "glossy", "mirror", "glass", "metallic-roughness"};
        EXPECT_STREQ(bsdf_type_name(b), kNames[int(t)]);
        BsdfType parsed;
        ASSERT_TRUE(parse_bsdf_type(bsdf_type_name(b), parsed));
        EXPECT_EQ(parsed, t);
        const BsdfParams q = bsdf_params(b);
        if (t != BsdfType::Glass) {
            EXPECT_EQ(q.base, p.base);
        }
        if (t == BsdfType::Glossy) {
            EXPECT_EQ(q.specular, p.specular);
            EXPECT_EQ(q.roughness, p.roughness);
        }
        if (t == BsdfType::Glass) {
            EXPECT_EQ(q.ior, p.ior);
        }
        if (t == BsdfType::MetallicRoughness) {
            EXPECT_EQ(q.specular, p.specular);
            EXPECT_EQ(q.roughness, p.roughness);
            EXPECT_EQ(q.ior, p.ior);
            EXPECT_EQ(q.metallic, p.metallic);
            EXPECT_EQ(q.transmission, p.transmission);
            EXPECT_EQ(q.specular_weight, p.specular_weight);
            EXPECT_EQ(q.thin_walled, p.thin_walled);
            EXPECT_EQ(q.attenuation_color, p.attenuation_color);
            EXPECT_EQ(q.attenuation_distance, p.attenuation_distance);
        }
    }
    BsdfType unused;
    EXPECT_FALSE(parse_bsdf_type("plastic", unused));
}

}  // namespace pv

// scene.json material overrides go through the same conversion: a glossy override keeps diffuse + specular <= 1
// (before, {"base_color": [0.9, ...], "specular": [0.5, ...]} made an albedo of 1.4), and a mirror reflects the
// "specular" colour given, else its base colour.
namespace pv {
TEST(MaterialParams, SceneFileOverridesKeepTheInvariants) {
    const std::string dir = std::filesystem::path(builtin_scene_path()).parent_path().string();
    const std::string json = R"({"obj": "cornell-box.obj", "materials": {
        "white": {"type": "glossy", "base_color": [0.9, 0.9, 0.9], "specular": [0.5, 0.2, 0.0], "roughness": 0.3},
        "red": {"type": "mirror", "specular": [0.7, 0.6, 0.5]},
        "green": {"type": "mirror"}}})";
    const Scene scene = load_scene_json_text(json, dir + "/overrides.json");
    int checked = 0;
    for (const Material& m : scene.materials) {
        if (m.name == "white") {
            const Glossy g = std::get<Glossy>(m.bsdf);
            for (int c = 0; c < 3; ++c) EXPECT_LE(g.diffuse[c] + g.specular[c], 1.f) << c;
            EXPECT_EQ(g.specular, vec3(0.5f, 0.2f, 0.f));
            EXPECT_EQ(g.alpha, 0.3f);
            ++checked;
        } else if (m.name == "red") {
            EXPECT_EQ(std::get<Mirror>(m.bsdf).reflectance, vec3(0.7f, 0.6f, 0.5f));
            ++checked;
        } else if (m.name == "green") {
            // The base colour of the MTL's green diffuse, not a near-black 0.04.
            EXPECT_GT(std::get<Mirror>(m.bsdf).reflectance.y, 0.1f);
            ++checked;
        }
    }
    EXPECT_EQ(checked, 3);
}
}  // namespace pv

// The metallic-roughness keys of a scene.json override (issue 27): parsed, clamped by make_bsdf(), and a bad value
// is one error naming the file and the key.
namespace pv {
TEST(MaterialParams, SceneFileMetallicRoughnessOverride) {
    const std::string dir = std::filesystem::path(builtin_scene_path()).parent_path().string();
    const std::string json = R"({"obj": "cornell-box.obj", "materials": {
        "white": {"type": "metallic-roughness", "base_color": [0.9, 0.8, 0.7], "metallic": 0.25, "roughness": 0.5,
                  "ior": 1.4, "transmission": 0.75, "specular_factor": 0.5, "specular": [1.0, 0.5, 0.25],
                  "thin_walled": false, "attenuation_color": [0.5, 0.6, 0.7], "attenuation_distance": 3}}})";
    const Scene scene = load_scene_json_text(json, dir + "/overrides.json");
    int checked = 0;
    for (const Material& m : scene.materials) {
        if (m.name != "white") continue;
        const auto& b = std::get<MetallicRoughness>(m.bsdf);
        EXPECT_EQ(b.base_color, vec3(0.9f, 0.8f, 0.7f));
        EXPECT_EQ(b.metallic, 0.25f);
        EXPECT_EQ(b.roughness, 0.5f);
        EXPECT_EQ(b.alpha, 0.25f);
        EXPECT_EQ(b.ior, 1.4f);
        EXPECT_EQ(b.transmission, 0.75f);
        EXPECT_EQ(b.specular, 0.5f);
        EXPECT_EQ(b.specular_color, vec3(1.f, 0.5f, 0.25f));
        EXPECT_FALSE(b.thin_walled);
        EXPECT_EQ(b.attenuation_color, vec3(0.5f, 0.6f, 0.7f));
        EXPECT_EQ(b.attenuation_distance, 3.f);
        EXPECT_EQ(oriented_eta(m.bsdf), 1.4f);
        ++checked;
    }
    EXPECT_EQ(checked, 1);
    const std::string bad = R"({"obj": "cornell-box.obj", "materials": {"white": {"metallic": 1.5}}})";
    try {
        load_scene_json_text(bad, dir + "/bad.json");
        ADD_FAILURE() << "accepted metallic 1.5";
    } catch (const std::exception& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("bad.json"), std::string::npos) << what;
        EXPECT_NE(what.find("metallic"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

// The viewer's material editor (ui/panel_scene.cpp) and scene.json overrides on a glTF material with a
// metallicRoughnessTexture: its texel scales the metallic factor at each hit, so a texel of metallic 0 under a factor
// of 1 is the dielectric of factor 0 there. After an edit (roughness 0.5 -> 0.6, base colour changed), the hit's BSDF
// must still be that dielectric: eval equal to the same material built with metallic 0, for directions over the
// hemisphere (before set_bsdf, the edit rebuilt the BSDF with the metal lobe alone and it evaluated to 0).
TEST(MaterialParams, EditingAMetallicRoughnessTexturedMaterialKeepsTheLobesItsTexelNeeds) {
    const Texture texel(1, 1, std::vector<vec4>{vec4(0.f, 1.f, 0.f, 1.f)});  // G: roughness x 1, B: metallic x 0
    HitTextures t;
    t.metal_rough = &texel;
    t.uv = vec2(0.5f);
    Material m;
    MetallicRoughness mr;
    mr.base_color = vec3(0.8f, 0.5f, 0.3f);
    mr.metallic = 1.f;
    mr.roughness = 0.5f;
    m.bsdf = make_metallic_roughness(mr);
    m.metallic_roughness_texture = 0;
    fit_bsdf_to_textures(m);  // as the glTF loader leaves it
    BsdfParams p = bsdf_params(m.bsdf);
    p.roughness = 0.6f;
    p.base = vec3(0.2f, 0.7f, 0.4f);
    set_bsdf(m, p);  // the panel's edit
    BsdfParams q = p;
    q.metallic = 0.f;
    Material dielectric;
    dielectric.bsdf = make_bsdf(q);
    const Bsdf a = hit_bsdf(m, t), b = hit_bsdf(dielectric, t);
    int compared = 0;
    for (float ct_o : {0.2f, 0.6f, 0.95f})
        for (float ct_i : {0.1f, 0.5f, 0.9f})
            for (float phi : {0.f, 1.f, 2.5f}) {
                const vec3 wo(std::sqrt(1.f - ct_o * ct_o), 0.f, ct_o);
                const float st = std::sqrt(1.f - ct_i * ct_i);
                const vec3 wi(st * std::cos(phi), st * std::sin(phi), ct_i);
                const vec3 fa = eval(a, wo, wi), fb = eval(b, wo, wi);
                ASSERT_GT(max_component(fb), 0.f);
                for (int k = 0; k < 3; ++k)
                    EXPECT_NEAR(fa[k], fb[k], 1e-5f * fb[k]) << ct_o << " " << ct_i << " " << phi;
                ++compared;
            }
    EXPECT_EQ(compared, 27);
    // Without the texture the edit is make_bsdf's alone.
    Material plain;
    plain.bsdf = make_metallic_roughness(mr);
    set_bsdf(plain, p);
    EXPECT_EQ(std::get<MetallicRoughness>(plain.bsdf).lobes, std::get<MetallicRoughness>(make_bsdf(p)).lobes);
}

// The panel's type combo carries parameters over by meaning: a diffuse material made metallic-roughness keeps its
// colour as a dielectric with glTF's specular colour 1 (F0 0.04, not the glossy default 0.04 squared), and a glTF
// dielectric made glossy keeps its diffuse colour under a 0.04 specular (its specular colour 1 as Fresnel reflectance
// left no diffuse at all), alpha = roughness^2; the same type changes nothing.
TEST(MaterialParams, ChangingTheTypeCarriesParametersOverByMeaning) {
    BsdfParams diffuse;
    diffuse.base = vec3(0.6f, 0.4f, 0.2f);
    const auto mr = std::get<MetallicRoughness>(make_bsdf(with_type(diffuse, BsdfType::MetallicRoughness)));
    EXPECT_EQ(mr.base_color, diffuse.base);
    EXPECT_EQ(mr.metallic, 0.f);
    EXPECT_NEAR(mr.spec_f0.x, 0.04f, 1e-6f);
    EXPECT_TRUE(mr.has(MetallicRoughness::kDiffuse));
    MetallicRoughness loaded;  // as the glTF loader gives a dielectric: specular colour 1
    loaded.base_color = diffuse.base;
    loaded.metallic = 0.f;
    loaded.roughness = 0.5f;
    const BsdfParams gltf = bsdf_params(make_metallic_roughness(loaded));
    const auto g = std::get<Glossy>(make_bsdf(with_type(gltf, BsdfType::Glossy)));
    EXPECT_EQ(g.diffuse, diffuse.base);
    EXPECT_NEAR(g.specular.x, 0.04f, 1e-6f);
    EXPECT_NEAR(g.alpha, 0.25f, 1e-6f);
    const BsdfParams same = with_type(gltf, BsdfType::MetallicRoughness);
    EXPECT_EQ(same.specular, gltf.specular);
    EXPECT_EQ(same.roughness, gltf.roughness);
}

}  // namespace pv

// KHR_materials_clearcoat and _sheen as scene.json overrides (the viewer's sliders edit the same BsdfParams): parsed,
// carried through bsdf_params() <-> make_bsdf() unchanged, hashed (a partial render of the coated scene is not merged
// with one of the uncoated scene), and a bad value is one error naming the file and the key.
namespace pv {
TEST(MaterialParams, SceneFileClearcoatAndSheenOverride) {
    const std::string dir = std::filesystem::path(builtin_scene_path()).parent_path().string();
    const std::string plain_json = R"({"obj": "cornell-box.obj", "materials": {
        "white": {"type": "metallic-roughness", "base_color": [0.9, 0.8, 0.7], "metallic": 0, "roughness": 0.5}}})";
    const std::string json = R"({"obj": "cornell-box.obj", "materials": {
        "white": {"type": "metallic-roughness", "base_color": [0.9, 0.8, 0.7], "metallic": 0, "roughness": 0.5,
                  "clearcoat": 0.75, "clearcoat_roughness": 0.25, "sheen_color": [1, 0.5, 0.25],
                  "sheen_roughness": 0.5}}})";
    const Scene plain = load_scene_json_text(plain_json, dir + "/plain.json");
    const Scene scene = load_scene_json_text(json, dir + "/layers.json");
    int checked = 0;
    for (const Material& m : scene.materials) {
        if (m.name != "white") continue;
        const auto& b = std::get<MetallicRoughness>(m.bsdf);
        EXPECT_EQ(b.clearcoat, 0.75f);
        EXPECT_EQ(b.clearcoat_roughness, 0.25f);
        EXPECT_EQ(b.coat_alpha, 0.0625f);
        EXPECT_EQ(b.sheen_color, vec3(1.f, 0.5f, 0.25f));
        EXPECT_EQ(b.sheen_roughness, 0.5f);
        EXPECT_TRUE(b.has(MetallicRoughness::kClearcoat) && b.has(MetallicRoughness::kSheen));
        const BsdfParams p = bsdf_params(m.bsdf);
        const MetallicRoughness again = std::get<MetallicRoughness>(make_bsdf(p));
        EXPECT_EQ(again.clearcoat, b.clearcoat);
        EXPECT_EQ(again.sheen_color, b.sheen_color);
        EXPECT_EQ(again.lobes, b.lobes);
        ++checked;
    }
    EXPECT_EQ(checked, 1);
    EXPECT_NE(scene_hash(scene, scene.materials, scene.environment),
              scene_hash(plain, plain.materials, plain.environment));
    std::vector<Material> edited = scene.materials;
    for (Material& m : edited)
        if (auto* b = std::get_if<MetallicRoughness>(&m.bsdf)) {
            b->sheen_roughness = 0.6f;
            prepare_metallic_roughness(*b);
        }
    EXPECT_NE(scene_hash(scene, scene.materials, scene.environment), scene_hash(scene, edited, scene.environment));
    const std::string bad = R"({"obj": "cornell-box.obj", "materials": {"white": {"clearcoat": 2}}})";
    try {
        load_scene_json_text(bad, dir + "/bad.json");
        ADD_FAILURE() << "accepted clearcoat 2";
    } catch (const std::exception& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("bad.json"), std::string::npos) << what;
        EXPECT_NE(what.find("clearcoat"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

// The clearcoat and sheen textures at a hit scale the factors (hit_bsdf): a texel of clearcoat R 0.5 and sheen
// colour (1, 0.5, 0) with alpha 0.5 gives the material of those scaled factors.
TEST(MaterialParams, ClearcoatAndSheenTexelsScaleTheFactors) {
    Scene s;
    s.textures.emplace_back(1, 1, std::vector<vec4>{vec4(0.5f, 0.25f, 0.f, 1.f)});  // clearcoat R, roughness G
    s.textures.emplace_back(1, 1, std::vector<vec4>{vec4(1.f, 0.5f, 0.f, 0.5f)});   // sheen RGB, roughness A
    Material m;
    MetallicRoughness mr;
    mr.metallic = 0.f;
    mr.roughness = 0.5f;
    mr.clearcoat = 0.8f;
    mr.clearcoat_roughness = 0.4f;
    mr.sheen_color = vec3(0.5f);
    mr.sheen_roughness = 0.8f;
    m.bsdf = make_metallic_roughness(mr);
    m.clearcoat_texture = m.clearcoat_roughness_texture = 0;
    m.sheen_color_texture = m.sheen_roughness_texture = 1;
    HitTextures t;
    t.layers = &m;
    t.textures = s.textures.data();
    ASSERT_TRUE(t.per_hit());
    const MetallicRoughness b = std::get<MetallicRoughness>(hit_bsdf(m, t));
    EXPECT_EQ(b.clearcoat, 0.4f);
    EXPECT_EQ(b.clearcoat_roughness, 0.1f);
    EXPECT_EQ(b.sheen_color, vec3(0.5f, 0.25f, 0.f));
    EXPECT_EQ(b.sheen_roughness, 0.4f);
    EXPECT_EQ(b.lobes, std::get<MetallicRoughness>(m.bsdf).lobes);
}
}  // namespace pv
