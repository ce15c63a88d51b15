// tests/render/test_hit_shading.cpp: the AOV pass and the sky guide's training walk shade a hit as the path tracer does
// (core/render/shading.h): glTF vertex colours (COLOR_0) multiply the denoiser's albedo, a normal map tilts its normal,
// and both change what the sky guide learns.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cmath>

#include "core/denoise/aov.h"
#include "core/render/sky_guide_training.h"
#include "tests/support/scenes.h"

namespace pv {
namespace {

// A 2 x 2 quad about the origin spanned by e1, e2 (normal e1 x e2), uvs (0,0)..(1,1) along e1 and e2 (so the
// normal map's tangent is e1, its bitangent e2), one material, a uniform vertex colour `color` and a one-texel normal
// map (float, no 8-bit rounding) encoding the tangent-space normal `tangent_n`.
std::shared_ptr<Scene> mapped_quad(vec3 e1, vec3 e2, const Bsdf& bsdf, vec3 color, vec3 tangent_n) {
    auto s = std::make_shared<Scene>();
    const vec3 o = -(e1 + e2);
    s->positions = {o, o + 2.f * e1, o + 2.f * (e1 + e2), o + 2.f * e2};
    s->triangles = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
    s->uvs = {vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 1)};
    s->uv_indices = s->triangles;
    s->colors = {color};
    s->color_indices = {uvec3(0), uvec3(0)};
    s->material_ids = {0, 0};
    s->textures.emplace_back(1, 1, std::vector<vec4>{vec4(0.5f * tangent_n + 0.5f, 1.f)});
    Material m;
    m.bsdf = bsdf;
    m.normal_texture = 0;
    s->materials = {m};
    return s;
}

TEST(HitShading, AovAlbedoIsBaseColourTimesVertexColourAndNormalIsTheMappedOne) {
    // A glTF plain diffuse (metallic 0) in the plane z = 0 facing +z; the map tilts +z toward +y (e2) by 30 degrees.
    MetallicRoughness mr;
    mr.base_color = vec3(0.9f, 0.8f, 0.6f);
    mr.metallic = 0.f;
    const vec3 color(0.5f, 0.25f, 1.f);
    const float tilt = 0.5235987756f;
    const vec3 mapped(0.f, std::sin(tilt), std::cos(tilt));
    const test::Tracer tracer(
        mapped_quad(vec3(1, 0, 0), vec3(0, 1, 0), make_metallic_roughness(mr), color, vec3(0.f, mapped.y, mapped.z)));
    Sampler sampler(0, SamplerKind::Independent);
    sampler.start(uvec2(0), 0);
    Ray ray;
    ray.o = vec3(0.1f, 0.2f, 3.f);
    ray.d = vec3(0.f, 0.f, -1.f);
    const FeatureSample f = trace_features(tracer, ray, sampler);
    EXPECT_NEAR(f.depth, 3.f, 1e-5f);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(f.albedo[k], mr.base_color[k] * color[k], 1e-6f) << k;  // the product, exactly (float rounding)
        EXPECT_NEAR(f.normal[k], mapped[k], 1e-5f) << k;  // the view is overhead: no grazing bend applies
    }
}

TEST(HitShading, SkyGuideTrainingSeesVertexColoursAndNormalMaps) {
    // A white floor (y = 0, facing +y) under a constant sky, seen from the +x side at 45 degrees.
    auto floor = [](vec3 color, vec3 tangent_n) {
        auto s = mapped_quad(vec3(1, 0, 0), vec3(0, 0, -1), Lambertian{vec3(0.8f)}, color, tangent_n);
        s->environment.background = vec3(1.f);
        s->camera.eye = vec3(3.f, 3.f, 0.f);
        s->camera.target = vec3(0.f);
        s->camera.vfov_deg = 20.f;
        return s;
    };
    RenderSettings rs;
    rs.seed = 7;
    rs.sky_guide = SkyGuideMode::On;
    auto train = [&](const std::shared_ptr<Scene>& s) {
        const TraceableScene ts(s);
        return train_sky_guide(ts, rs, Camera(s->camera, 16, 16));
    };
    // The sky low toward -x: its bin (y in [0, 1/4], phi in [180, 202.5] degrees) lies below the map's normal tilted
    // 60 degrees toward +x (where 0.866 x + 0.5 y <= 0), so a Lambertian about that normal reflects none of it.
    const vec3 low_west = glm::normalize(vec3(-1.f, 0.15f, 0.1f));
    const vec3 flat(0.f, 0.f, 1.f), tilted(std::sin(1.0471976f), 0.f, std::cos(1.0471976f));
    const auto plain = train(floor(vec3(1.f), flat));
    ASSERT_NE(plain, nullptr);
    EXPECT_GT(plain->pdf(vec3(0.f), low_west), 0.f);
    const auto mapped = train(floor(vec3(1.f), tilted));
    ASSERT_NE(mapped, nullptr);
    EXPECT_EQ(mapped->pdf(vec3(0.f), low_west), 0.f);
    EXPECT_GT(mapped->pdf(vec3(0.f), glm::normalize(vec3(1.f, 0.3f, 0.1f))), 0.f);  // the sky the tilt faces
    // A black vertex colour reflects no sky at all: nothing to learn, no guide.
    EXPECT_EQ(train(floor(vec3(0.f), flat)), nullptr);
}

}  // namespace
}  // namespace pv
