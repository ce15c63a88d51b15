// tests/scene/test_normal_map.cpp: glTF normalTexture (core/render/normal_map.h): a flat quad whose normal map tilts
// the normal by a known angle is lit as the quad geometrically tilted by that angle (direct lighting from a directional
// light, in closed form), and a flat map (0.5, 0.5, 1) renders the image of no map bit for bit.
// Test kinds: unit; analytic: NormalMapLighting
#include <gtest/gtest.h>

#include <cmath>

#include "core/render/normal_map.h"
#include "tests/support/scenes.h"

namespace pv {
namespace {

constexpr float kTilt = 0.5235987756f;  // 30 degrees

// A unit quad about the origin spanned by e1, e2 (normal e1 x e2), uvs (0,0)..(1,1) along e1 and e2, one Lambertian
// material, lit by a directional light arriving from `toward_light` with irradiance 1; a black sky.
std::shared_ptr<Scene> lit_quad(vec3 e1, vec3 e2, vec3 toward_light) {
    auto s = std::make_shared<Scene>();
    const vec3 o = -0.5f * (e1 + e2);
    s->positions = {o, o + e1, o + e1 + e2, o + e2};
    s->triangles = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
    s->uvs = {vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 1)};
    s->uv_indices = s->triangles;
    s->material_ids = {0, 0};
    Material m;
    m.bsdf = Lambertian{vec3(0.8f)};
    s->materials = {m};
    PunctualLight l;
    l.type = PunctualLight::Type::Directional;
    l.direction = -glm::normalize(toward_light);
    l.intensity = vec3(1.f);
    s->punctual_lights = {l};
    s->camera.eye = vec3(0, 0, 3);
    s->camera.target = vec3(0);
    s->camera.up = vec3(0, 1, 0);
    s->camera.vfov_deg = 10.f;
    return s;
}

// The normal map of one texel, float (no 8-bit rounding), encoding the tangent-space normal n.
uint32_t add_normal_map(Scene& s, vec3 n) {
    s.textures.emplace_back(1, 1, std::vector<vec4>{vec4(0.5f * n + 0.5f, 1.f)});
    return uint32_t(s.textures.size() - 1);
}

vec3 centre(const Film& f) {
    const auto& p = f.pixel(f.width() / 2, f.height() / 2);
    return vec3(float(p.sum[0]), float(p.sum[1]), float(p.sum[2])) / float(p.n);
}

TEST(NormalMapLighting, TiltedMapLightsAsTheTiltedQuadInClosedForm) {
    const vec3 toward_light = glm::normalize(vec3(0.f, 0.5f, 1.f));
    const vec3 tilted_n(0.f, std::sin(kTilt), std::cos(kTilt));
    // The map tilts +z toward +y (B, up the uvs' v) by 30 degrees; the geometric quad is turned by the same angle.
    auto mapped = lit_quad(vec3(1, 0, 0), vec3(0, 1, 0), toward_light);
    mapped->materials[0].normal_texture = add_normal_map(*mapped, vec3(0.f, std::sin(kTilt), std::cos(kTilt)));
    auto tilted = lit_quad(vec3(1, 0, 0), vec3(0, std::cos(kTilt), -std::sin(kTilt)), toward_light);
    auto flat = lit_quad(vec3(1, 0, 0), vec3(0, 1, 0), toward_light);
    RenderSettings rs;
    rs.seed = 3;
    const int w = 9, h = 9, spp = 4;
    const vec3 a = centre(test::render_with_renderer(mapped, mapped->camera, rs, w, h, spp));
    const vec3 b = centre(test::render_with_renderer(tilted, tilted->camera, rs, w, h, spp));
    const vec3 c = centre(test::render_with_renderer(flat, flat->camera, rs, w, h, spp));
    // Direct light only (a black sky, nothing else to bounce from): albedo / pi x E x cos, exactly.
    const float want = 0.8f / 3.14159265f * glm::dot(tilted_n, toward_light);
    const float want_flat = 0.8f / 3.14159265f * toward_light.z;
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(a[k], want, 1e-4f * want) << "normal-mapped";
        EXPECT_NEAR(b[k], want, 1e-4f * want) << "geometrically tilted";
        EXPECT_NEAR(c[k], want_flat, 1e-4f * want_flat) << "no map";
    }
    EXPECT_GT(std::fabs(want - want_flat), 0.02f * want);  // the tilt changes the answer
    // The scale multiplies the map's x and y: scale 0 is no tilt.
    mapped->materials[0].normal_scale = 0.f;
    const vec3 d = centre(test::render_with_renderer(mapped, mapped->camera, rs, w, h, spp));
    EXPECT_NEAR(d.x, want_flat, 1e-4f * want_flat);
}

TEST(NormalMap, TangentsFromTheFileOrTheUvsOrAnyFrameWhereUvsAreDegenerate) {
    auto s = lit_quad(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1));
    SurfacePoint sf;
    sf.ng = sf.ns = vec3(0, 0, 1);
    sf.b0 = 1.f / 3.f;
    const vec3 texel = 0.5f * glm::normalize(vec3(1.f, 0.f, 1.f)) + 0.5f;  // 45 degrees toward T
    // From the uvs: T = dp/du = +x.
    vec3 n = normal_mapped(*s, 0, 1.f / 3.f, 1.f / 3.f, sf, texel, 1.f);
    EXPECT_NEAR(n.x, std::sqrt(0.5f), 1e-5f);
    EXPECT_NEAR(n.z, std::sqrt(0.5f), 1e-5f);
    // Mirrored uvs (u decreasing along x): T = -x.
    s->uvs = {vec2(1, 0), vec2(0, 0), vec2(0, 1), vec2(1, 1)};
    n = normal_mapped(*s, 0, 1.f / 3.f, 1.f / 3.f, sf, texel, 1.f);
    EXPECT_NEAR(n.x, -std::sqrt(0.5f), 1e-5f);
    // The file's tangents win over the uvs: T = +y, w = -1 (B = -(N x T) = +x).
    s->tangents = {vec4(0, 1, 0, -1)};
    s->tangent_indices = {uvec3(0), uvec3(0)};
    n = normal_mapped(*s, 0, 1.f / 3.f, 1.f / 3.f, sf, texel, 1.f);
    EXPECT_NEAR(n.y, std::sqrt(0.5f), 1e-5f);
    n = normal_mapped(*s, 0, 1.f / 3.f, 1.f / 3.f, sf, 0.5f * glm::normalize(vec3(0.f, 1.f, 1.f)) + 0.5f, 1.f);
    EXPECT_NEAR(n.x, std::sqrt(0.5f), 1e-5f);
    // Degenerate uvs, no tangents: some frame about N, still a unit normal tilted by 45 degrees.
    s->tangents.clear();
    s->tangent_indices.clear();
    s->uvs = {vec2(0.3f), vec2(0.3f), vec2(0.3f), vec2(0.3f)};
    n = normal_mapped(*s, 0, 1.f / 3.f, 1.f / 3.f, sf, texel, 1.f);
    EXPECT_NEAR(glm::length(n), 1.f, 1e-5f);
    EXPECT_NEAR(n.z, std::sqrt(0.5f), 1e-5f);
    // A flat texel gives N bit for bit; one tilting below the surface keeps N.
    sf.ns = glm::normalize(vec3(0.1f, 0.2f, 0.9f));
    EXPECT_EQ(normal_mapped(*s, 0, 0.2f, 0.3f, sf, vec3(0.5f, 0.5f, 1.f), 1.f), sf.ns);
    EXPECT_EQ(normal_mapped(*s, 0, 0.2f, 0.3f, sf, vec3(0.f, 0.5f, 0.5f), 20.f), sf.ns);
}

// A map's normal tilted 30 degrees away from a viewer who sweeps from overhead down to grazing (and the same seen
// from below the surface): where the mirror reflection about the mapped normal stays above the surface the normal is
// kept bit for bit; below that it is bent toward the geometric normal, in their plane, just so far that the reflection
// leaves at min(0.9 cos, 0.01) above the surface (Cycles' rule), and it changes continuously with the view: no jump
// to the flat normal (what Veach's rule gave before, sharp-edged flat patches in the bumps at grazing views).
TEST(NormalMap, GrazingViewsBendTheMappedNormalContinuouslyAsCyclesDoes) {
    const float tilt = glm::radians(30.f);
    for (const float side : {1.f, -1.f}) {
        const vec3 ng(0.f, 0.f, side);
        const vec3 n(0.f, std::sin(tilt), side * std::cos(tilt));  // tilted toward +y
        vec3 last(0.f);
        int kept = 0, bent = 0;
        for (int k = 1; k <= 890; ++k) {
            const float e = glm::radians(0.1f * float(k));                // elevation of the view
            const vec3 wo = vec3(0.f, -std::cos(e), side * std::sin(e));  // from the -y side: away from the tilt
            const vec3 b = valid_reflection_normal(ng, wo, n);
            const vec3 r = 2.f * glm::dot(b, wo) * b - wo;
            const float threshold = std::min(0.9f * std::sin(e), 0.01f);
            const bool valid = glm::dot(2.f * glm::dot(n, wo) * n - wo, ng) >= threshold;
            ASSERT_NEAR(glm::length(b), 1.f, 1e-5f) << k;
            EXPECT_EQ(b.x, 0.f) << "in the plane of n and ng";
            EXPECT_GE(glm::dot(b, ng), std::cos(tilt) - 1e-6f) << "between n and ng";
            EXPECT_GT(glm::dot(b, wo), 0.f) << "wo in front of it";
            if (valid) {
                EXPECT_EQ(b, n) << "kept where the reflection is valid, elevation " << 0.1f * float(k);
                ++kept;
            } else {
                EXPECT_NEAR(glm::dot(r, ng), threshold, 2e-4f) << "elevation " << 0.1f * float(k);
                EXPECT_GT(glm::dot(b, ng), glm::dot(n, ng)) << "bent toward ng";
                ++bent;
            }
            if (k > 1) {
                EXPECT_LT(glm::length(b - last), 0.01f) << "continuous at elevation " << 0.1f * float(k);
            }
            last = b;
        }
        EXPECT_GT(kept, 100);
        EXPECT_GT(bent, 100);
    }
    // A view toward the tilt, and a normal along ng: nothing to bend.
    const vec3 n = vec3(0.f, std::sin(tilt), std::cos(tilt));
    const vec3 toward = glm::normalize(vec3(0.f, 1.f, 0.02f));
    EXPECT_EQ(valid_reflection_normal(vec3(0, 0, 1), toward, n), n);
    EXPECT_EQ(valid_reflection_normal(vec3(0, 0, 1), glm::normalize(vec3(0.f, -1.f, 0.02f)), vec3(0, 0, 1)),
              vec3(0, 0, 1));
}

TEST(NormalMap, FlatMapRendersTheImageOfNoMapBitForBit) {
    auto plain = std::make_shared<Scene>(*test::cornell_box());
    auto flat = std::make_shared<Scene>(*plain);
    const uint32_t tex = add_normal_map(*flat, vec3(0, 0, 1));
    for (Material& m : flat->materials) m.normal_texture = tex;
    RenderSettings rs;
    rs.seed = 8;
    const int w = 24, h = 24, spp = 8;
    const Film a = test::render_with_renderer(plain, plain->camera, rs, w, h, spp);
    const Film b = test::render_with_renderer(flat, flat->camera, rs, w, h, spp);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < 3; ++k) ASSERT_EQ(a.pixel(x, y).sum[k], b.pixel(x, y).sum[k]) << x << "," << y;
}

}  // namespace
}  // namespace pv
