// tests/render/test_traceable_scene.cpp: the scene prepared for tracing (core/render/traceable_scene.h): its one light
// interface over emissive triangles, sky and sun (selection probabilities, sampling against its own pdfs by
// chi-square), picking, and material and environment edits.
// Test kinds: unit; statistical: Chi2CombinedLight
#include <gtest/gtest.h>

#include "core/render/surface.h"
#include "core/render/traceable_scene.h"
#include "core/sampling/rng.h"
#include "core/sampling/warp.h"
#include "core/scene/environment.h"
#include "tests/support/chi2.h"
#include "tests/support/scenes.h"

namespace pv {
namespace {

// A light quad above the origin (its front facing up, away from it: the pdfs do not depend on that), optionally a
// constant sky and a wide sun off to the side.
std::shared_ptr<Scene> lit_scene(bool quad, vec3 sky, vec3 sun_irradiance) {
    auto scene = std::make_shared<Scene>();
    Material light;
    light.emission = vec3(3.f, 2.f, 1.f);
    Material grey;
    const uint32_t ml = test::add_material(*scene, light), mg = test::add_material(*scene, grey);
    test::add_quad(*scene, vec3(-1, 2, -1), vec3(-1, 2, 1), vec3(1, 2, 1), vec3(1, 2, -1), quad ? ml : mg);
    scene->environment.background = sky;
    scene->environment.sun_direction = vec3(1.f, 0.3f, 0.f);
    scene->environment.sun_angular_radius_deg = 10.f;  // wide: the chi-square grid resolves it
    scene->environment.sun_irradiance = sun_irradiance;
    return scene;
}

TEST(TraceableScene, SelectionProbabilityFollowsWhatShines) {
    struct Case {
        bool quad;
        vec3 sky, sun;
        float p_env;
        bool has_lights, select_draw;
    };
    const Case cases[] = {
        {true, vec3(0.f), vec3(0.f), 0.f, true, true},     // triangles only
        {false, vec3(0.5f), vec3(0.f), 1.f, true, false},  // sky only: no selection draw
        {false, vec3(0.f), vec3(2.f), 1.f, true, false},   // sun only
        {true, vec3(0.5f), vec3(2.f), 0.5f, true, true},   // both: half each
        {false, vec3(0.f), vec3(0.f), 0.f, false, true},   // nothing shines
    };
    for (const Case& c : cases) {
        const TraceableScene ts(lit_scene(c.quad, c.sky, c.sun));
        EXPECT_EQ(ts.environment_selection_probability(), c.p_env) << c.quad << " " << c.sky.x << " " << c.sun.x;
        EXPECT_EQ(ts.has_lights(), c.has_lights);
        EXPECT_EQ(ts.light_selection_draw(), c.select_draw);
    }
}

// The direction pdf of the light interface: light_pdf_escape everywhere plus light_pdf_hit where the direction
// meets an emissive triangle (nothing else in the scene occludes the quad from the origin).
double light_direction_pdf(const TraceableScene& ts, vec3 ref, vec3 w) {
    double pdf = ts.light_pdf_escape(ref, w);
    Ray ray;
    ray.o = ref;
    ray.d = w;
    Hit hit;
    if (ts.intersect(ray, hit)) {
        const SurfacePoint sf = surface_point(ts.scene(), hit);
        pdf += ts.light_pdf_hit(hit.prim, ref, vec3(0.f), sf.p, sf.ng);
    }
    return pdf;
}

// sample_light over triangles, sky and sun together draws directions with the density light_pdf_hit and
// light_pdf_escape give them (selection probabilities included): chi-square, and the pdf integrates to 1.
TEST(Chi2CombinedLight, LightSamplesFollowTheCombinedPdf) {
    const vec3 ref(0.f);
    for (const bool quad : {true, false}) {
        const TraceableScene ts(lit_scene(quad, vec3(0.5f), vec3(2.f)));
        test::Chi2Options o;
        o.sample_count = 400000;
        o.test_count = 2;
        const auto r = test::chi2_test(
            [&](Pcg32& g) -> std::optional<vec3> {
                const float us = g.next_float();
                const float u0 = g.next_float();
                const vec2 u(u0, g.next_float());
                LightSample ls;
                if (!ts.sample_light(ref, vec3(0.f), us, u, ls)) return std::nullopt;
                // The sample's own pdf is the interface's pdf of its direction.
                const double p = light_direction_pdf(ts, ref, ls.wi);
                if (std::isinf(ls.dist)) {
                    EXPECT_NEAR(ls.pdf, ts.light_pdf_escape(ref, ls.wi), 1e-4 * ls.pdf);
                } else {
                    EXPECT_NEAR(ls.pdf, p - ts.light_pdf_escape(ref, ls.wi), 2e-3 * ls.pdf);
                }
                return ls.wi;
            },
            [&](vec3 w) { return light_direction_pdf(ts, ref, w); }, o);
        EXPECT_TRUE(r.passed) << "quad " << quad << ": " << r.message;
        EXPECT_NEAR(r.pdf_integral, 1.0, 1e-2) << r.message;
    }
}

TEST(TraceableScene, PickFindsTheSurfaceUnderAPixel) {
    const TraceableScene ts(lit_scene(true, vec3(0.f), vec3(0.f)));
    CameraDesc d;
    d.eye = vec3(0.f, 0.f, 0.f);
    d.target = vec3(0.f, 1.f, 0.f);
    d.up = vec3(0.f, 0.f, 1.f);
    d.vfov_deg = 40.f;
    const Camera camera(d, 64, 64);
    const std::optional<PickResult> hit = ts.pick(camera, vec2(32.f, 32.f));
    ASSERT_TRUE(hit.has_value());
    EXPECT_LT(hit->triangle, 2u);
    EXPECT_EQ(hit->material, 0u);
    EXPECT_NEAR(hit->distance, 2.f, 1e-5f);
    EXPECT_NEAR(hit->position.y, 2.f, 1e-5f);
    d.target = vec3(0.f, -1.f, 0.f);  // looking away: nothing
    EXPECT_FALSE(ts.pick(Camera(d, 64, 64), vec2(32.f, 32.f)).has_value());
}

// Edits rebuild the lights and the selection: an emitter switched off leaves the sky as the only light.
TEST(TraceableScene, EditsUpdateLightsAndSelection) {
    TraceableScene ts(lit_scene(true, vec3(0.5f), vec3(0.f)));
    EXPECT_EQ(ts.environment_selection_probability(), 0.5f);
    std::vector<Material> edited = ts.materials();
    edited[0].emission = vec3(0.f);
    ts.set_materials(edited);
    EXPECT_TRUE(ts.triangle_lights().empty());
    EXPECT_EQ(ts.environment_selection_probability(), 1.f);
    EnvironmentSettings dark = ts.environment_settings();
    dark.background = vec3(0.f);
    ts.set_environment(dark);
    EXPECT_FALSE(ts.has_lights());
    EXPECT_EQ(ts.environment_settings(), dark);
    ts.set_materials(ts.scene().materials);
    EXPECT_EQ(ts.environment_selection_probability(), 0.f);
    EXPECT_EQ(ts.triangle_lights().size(), 2u);
}

// emitted_escape_and_pdf (the path tracer's escaped ray: one texel search) gives exactly emitted_escape and
// light_pdf_escape, for a constant sky, the default one-column sky, a 2D map, each with a sun, and with portals
// (the mixed pdf), on directions anywhere, in the sun and on texel edges.
TEST(TraceableScene, EscapeRadianceAndPdfInOneSearchAreTheSeparateValues) {
    auto with_sun = [](std::shared_ptr<Scene> s) {
        s->environment.sun_direction = vec3(0.4f, 0.8f, -0.3f);
        s->environment.sun_angular_radius_deg = 3.f;
        s->environment.sun_irradiance = vec3(4.f);
        return s;
    };
    auto constant = with_sun(lit_scene(true, vec3(0.6f), vec3(0.f)));
    auto default_sky = with_sun(std::make_shared<Scene>());
    default_sky->textures.push_back(make_default_sky());
    default_sky->environment_map = 0;
    default_sky->environment.rotation_deg = 37.f;
    auto map = with_sun(std::make_shared<Scene>());
    {
        Pcg32 rng(5, 6);
        std::vector<vec4> texels(24 * 12);
        for (vec4& t : texels) t = vec4(rng.next_float(), rng.next_float(), 4.f * rng.next_float(), 1.f);
        map->textures.emplace_back(24, 12, std::move(texels));
        map->environment_map = 0;
        map->environment.rotation_deg = -71.f;
    }
    auto portals = std::make_shared<Scene>(*map);  // the map and its sun, with a portal
    portals->portals.push_back(Portal{vec3(-0.5f, 1.f, -0.5f), vec3(1.f, 0.f, 0.f), vec3(0.f, 0.f, 1.f)});
    struct Case {
        std::shared_ptr<Scene> scene;
        const char* name;
    };
    const Case cases[] = {
        {constant, "constant"}, {default_sky, "default sky"}, {map, "24x12 map"}, {portals, "24x12 map, portal"}};
    for (const Case& c : cases) {
        const TraceableScene ts(c.scene);
        const Environment& env = ts.environment();
        const vec3 ref(0.1f, 0.2f, -0.05f);
        std::vector<vec3> dirs;
        Pcg32 rng(11, 12);
        for (int i = 0; i < 20000; ++i)
            dirs.push_back(square_to_uniform_sphere(vec2(rng.next_float(), rng.next_float())));
        for (int i = 0; i < 5000; ++i) {  // the lights' own samples: in the sun, through the portal
            LightSample ls;
            if (ts.sample_light(ref, vec3(0.f), rng.next_float(), vec2(rng.next_float(), rng.next_float()), ls))
                dirs.push_back(ls.wi);
        }
        for (int row = 0; row <= 12; ++row)  // texel corners of the 2D map (also rows of the others)
            for (int col = 0; col < 24; ++col) dirs.push_back(env.uv_to_direction(vec2(col / 24.f, row / 12.f)));
        int in_sun = 0, through_portal = 0;
        for (const vec3& d : dirs) {
            float pdf = -1.f;
            const vec3 le = ts.emitted_escape_and_pdf(ref, d, &pdf);
            const vec3 le_alone = ts.emitted_escape(d);
            const float pdf_alone = ts.light_pdf_escape(ref, d);
            ASSERT_EQ(le.x, le_alone.x) << c.name;
            ASSERT_EQ(le.y, le_alone.y) << c.name;
            ASSERT_EQ(le.z, le_alone.z) << c.name;
            ASSERT_EQ(pdf, pdf_alone) << c.name << " " << d.x << "," << d.y << "," << d.z;
            in_sun += env.pdf_sun(d) > 0.f ? 1 : 0;
            through_portal += ts.portal_pdf(ref, d) > 0.f ? 1 : 0;
        }
        EXPECT_GT(in_sun, 100) << c.name;  // the sun's part of both values is exercised
        if (!c.scene->portals.empty()) {
            EXPECT_GT(through_portal, 100) << c.name;
        }
    }
    float pdf = -1.f;  // nothing shines
    const TraceableScene dark(lit_scene(true, vec3(0.f), vec3(0.f)));
    EXPECT_EQ(dark.emitted_escape_and_pdf(vec3(0.f), vec3(0.f, 1.f, 0.f), &pdf), vec3(0.f));
    EXPECT_EQ(pdf, 0.f);
}

}  // namespace
}  // namespace pv
