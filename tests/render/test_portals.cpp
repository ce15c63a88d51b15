// tests/render/test_portals.cpp: light portals (Scene::portals, core/render/traceable_scene.h): portal direction
// sampling against its pdf (chi-square), the environment mixture with portals integrating to 1 and matching its
// samples' pdfs, the same image with and without a portal (in the opening, and misplaced) within a confidence interval
// from the sample variance, and the scene file's "portals" key with its errors.
// Test kinds: unit; statistical: PortalSampling
#include <gtest/gtest.h>

#include <filesystem>

#include "core/base/error.h"
#include "core/load/scene_file.h"
#include "tests/support/chi2.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

// A closed unit room [0,1]^3 with a square window 0.3 x 0.3 in the wall x = 1 (y, z in 0.35..0.65), lit by a
// constant sky (and optionally a wide sun shining in through the window). The portal is the window's opening.
std::shared_ptr<Scene> window_room(const std::vector<Portal>& portals, bool sun) {
    auto scene = std::make_shared<Scene>();
    Material wall;
    wall.bsdf = Lambertian{vec3(0.6f)};
    const uint32_t m = test::add_material(*scene, wall);
    const vec3 p000(0, 0, 0), p100(1, 0, 0), p110(1, 1, 0), p010(0, 1, 0);
    const vec3 p001(0, 0, 1), p101(1, 0, 1), p111(1, 1, 1), p011(0, 1, 1);
    test::add_quad(*scene, p000, p010, p110, p100, m);  // z = 0
    test::add_quad(*scene, p001, p101, p111, p011, m);  // z = 1
    test::add_quad(*scene, p000, p100, p101, p001, m);  // y = 0 (floor)
    test::add_quad(*scene, p010, p011, p111, p110, m);  // y = 1
    test::add_quad(*scene, p000, p001, p011, p010, m);  // x = 0
    // x = 1 around the hole: four strips.
    const float a = 0.35f, b = 0.65f;
    test::add_quad(*scene, vec3(1, 0, 0), vec3(1, a, 0), vec3(1, a, 1), vec3(1, 0, 1), m);  // below
    test::add_quad(*scene, vec3(1, b, 0), vec3(1, 1, 0), vec3(1, 1, 1), vec3(1, b, 1), m);  // above
    test::add_quad(*scene, vec3(1, a, 0), vec3(1, b, 0), vec3(1, b, a), vec3(1, a, a), m);  // z < a
    test::add_quad(*scene, vec3(1, a, b), vec3(1, b, b), vec3(1, b, 1), vec3(1, a, 1), m);  // z > b
    scene->environment.background = vec3(1.f, 0.9f, 0.8f);
    if (sun) {
        scene->environment.sun_direction = vec3(1.f, 0.6f, 0.1f);
        scene->environment.sun_angular_radius_deg = 8.f;
        scene->environment.sun_irradiance = vec3(4.f);
    }
    scene->portals = portals;
    scene->camera.eye = vec3(0.15f, 0.6f, 0.5f);
    scene->camera.target = vec3(1.f, 0.3f, 0.5f);
    scene->camera.vfov_deg = 80.f;
    return scene;
}

const Portal kWindow{vec3(1.f, 0.35f, 0.35f), vec3(0.f, 0.3f, 0.f), vec3(0.f, 0.f, 0.3f)};
// Misplaced: half on the wall above the window (covering only its top third), plus one on the back wall x = 0.
const Portal kMisplacedA{vec3(1.f, 0.55f, 0.2f), vec3(0.f, 0.4f, 0.f), vec3(0.f, 0.f, 0.6f)};
const Portal kMisplacedB{vec3(0.f, 0.2f, 0.2f), vec3(0.f, 0.f, 0.5f), vec3(0.f, 0.5f, 0.f)};

TEST(Portals, ProbabilityOnlyWithPortalsAndALitEnvironment) {
    EXPECT_EQ(TraceableScene(window_room({}, false)).portal_probability(), 0.f);
    const TraceableScene with(window_room({kWindow}, false));
    EXPECT_EQ(with.portal_probability(), TraceableScene::kPortalProbability);
    EXPECT_TRUE(with.light_selection_draw());  // the environment is the only light, but the draw picks a portal
    auto dark = window_room({kWindow}, false);
    dark->environment.background = vec3(0.f);
    EXPECT_EQ(TraceableScene(dark).portal_probability(), 0.f);
}

// Portal sampling alone (two portals of different areas, one seen edge-on from some points) draws directions
// with the density portal_pdf gives them: chi-square, and that pdf integrates to 1 over the sphere.
TEST(PortalSampling, PortalDirectionsFollowTheirPdf) {
    const TraceableScene ts(window_room({kWindow, kMisplacedB}, false));
    for (const vec3 ref : {vec3(0.5f, 0.5f, 0.5f), vec3(0.2f, 0.1f, 0.8f)}) {
        test::Chi2Options o;
        o.sample_count = 300000;
        o.test_count = 2;
        const auto r = test::chi2_test(
            [&](Pcg32& g) -> std::optional<vec3> {
                const float pick = g.next_float();
                const float u0 = g.next_float();
                vec3 wi;
                if (!ts.sample_portal(ref, pick, vec2(u0, g.next_float()), wi)) return std::nullopt;
                return wi;
            },
            [&](vec3 w) { return double(ts.portal_pdf(ref, w)); }, o);
        EXPECT_TRUE(r.passed) << r.message;
        EXPECT_NEAR(r.pdf_integral, 1.0, 1e-2) << r.message;
    }
}

// The whole environment sample (sky, sun and portals mixed) follows light_pdf_escape, its own pdf is that value,
// and it integrates to 1; a reference point outside the room works the same.
TEST(PortalSampling, EnvironmentMixtureFollowsItsPdf) {
    const TraceableScene ts(window_room({kWindow, kMisplacedA}, true));
    for (const vec3 ref : {vec3(0.4f, 0.45f, 0.55f), vec3(1.5f, 0.2f, 0.5f)})
        test::expect_environment_samples_follow_pdf(ts, ref);
}

test::PixelStats render_stats(std::shared_ptr<const Scene> scene, uint32_t seed, int spp) {
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // the bounds use the i.i.d. sample variance
    s.seed = seed;
    const CameraDesc cam = scene->camera;
    return test::PixelStats::from_film(test::render_with_renderer(std::move(scene), cam, s, 12, 12, spp, 2));
}

// The same room renders the same image (per-pixel Welch with Sidak, and the total mean) without portals, with the
// window's portal, and with misplaced portals (the environment's own sampling keeps every direction covered).
TEST(PortalSampling, RenderAgreesWithAndWithoutPortals) {
    const int spp = 256;
    const auto none = render_stats(window_room({}, true), 3, spp);
    const auto window = render_stats(window_room({kWindow}, true), 4, spp);
    const auto misplaced = render_stats(window_room({kMisplacedA, kMisplacedB}, true), 5, spp);
    const auto c1 = test::compare_images(none, window);
    EXPECT_TRUE(c1.passed) << "window portal: " << c1.describe();
    const auto c2 = test::compare_images(none, misplaced);
    EXPECT_TRUE(c2.passed) << "misplaced portals: " << c2.describe();
    // And the portal pays here: the window's image is less noisy.
    EXPECT_LT(window.total_mean_variance(), none.total_mean_variance());
}

std::string cornell_dir() { return std::filesystem::path(builtin_scene_path()).parent_path().string(); }

// The largest portal a scene file accepts (edges of 1e9) still has a finite, positive pdf through its middle:
// t^2 |n| / (A |cos|) = 3^2 x 1e18 / (1e18 x 1e18).
TEST(Portals, LargestAcceptedPortalKeepsAFinitePdf) {
    const Portal huge{vec3(-5e8f, -5e8f, 3.f), vec3(1e9f, 0.f, 0.f), vec3(0.f, 1e9f, 0.f)};
    const TraceableScene ts(window_room({huge}, false));
    const float pdf = ts.portal_pdf(vec3(0.f), vec3(0.f, 0.f, 1.f));
    EXPECT_TRUE(std::isfinite(pdf));
    EXPECT_NEAR(pdf, 9e-18f, 9e-18f * 1e-4f);
}

TEST(Portals, SixtyFourPortalsAreRead) {
    std::string list = "[";
    for (int i = 0; i < 64; ++i)
        list += std::string(i ? "," : "") + R"({"corner": [0,0,0], "edge1": [1,0,0], "edge2": [0,1,0]})";
    const Scene s =
        load_scene_json_text(R"({"obj": "cornell-box.obj", "portals": )" + list + "]}", cornell_dir() + "/p.json");
    EXPECT_EQ(s.portals.size(), 64u);
}

TEST(Portals, SceneFileReadsPortals) {
    const Scene s = load_scene_json_text(
        R"({"obj": "cornell-box.obj", "portals": [{"corner": [1, 2, 3], "edge1": [0, 1, 0], "edge2": [0, 0, 2]}]})",
        cornell_dir() + "/p.json");
    ASSERT_EQ(s.portals.size(), 1u);
    EXPECT_EQ(s.portals[0].corner, vec3(1, 2, 3));
    EXPECT_EQ(s.portals[0].edge1, vec3(0, 1, 0));
    EXPECT_EQ(s.portals[0].edge2, vec3(0, 0, 2));
}

TEST(Portals, BadPortalJsonNamesFileAndKey) {
    const struct {
        const char* portals;
        const char* expect;
    } cases[] = {
        {R"({"corner": [0,0,0]})", "p.json: /portals: expected an array"},
        {R"([{"corner": [0,0,0], "edge1": [1,0,0]}])", "p.json: /portals/0/edge2: missing"},
        {R"([{"corner": [0,0,"x"], "edge1": [1,0,0], "edge2": [0,1,0]}])", "p.json: /portals/0/corner/2: expected"},
        {R"([{"corner": [0,0,0], "edge1": [1,0,0], "edge2": [2,0,0]}])", "p.json: /portals/0: degenerate portal"},
        {R"([{"corner": [0,0,0], "edge1": [0,0,0], "edge2": [0,1,0]}])", "p.json: /portals/0: degenerate portal"},
        {R"([{"corner": [0,0,0], "edge1": [1,0,0], "edge2": [0,1e300,0]}])", "p.json: /portals/0/edge2/1: expected"},
        {R"([3])", "p.json: /portals/0: expected an object"},
        // Longer edges would overflow |edge1 x edge2|^2 in the portal's pdf (it was 0 for every direction).
        {R"([{"corner": [0,0,0], "edge1": [1e12,0,0], "edge2": [0,1e12,0]}])", "p.json: /portals/0/edge1/0: expected"},
        // Issue 26, defect 10: each light sample tests every portal; more than 64 are refused.
        {nullptr, "p.json: /portals: 65 portals; at most 64 are supported"},
    };
    std::string many = "[";
    for (int i = 0; i < 65; ++i)
        many += std::string(i ? "," : "") + R"({"corner": [0,0,0], "edge1": [1,0,0], "edge2": [0,1,0]})";
    many += "]";
    for (const auto& c : cases) {
        const std::string text =
            std::string(R"({"obj": "cornell-box.obj", "portals": )") + (c.portals ? c.portals : many.c_str()) + "}";
        try {
            load_scene_json_text(text, cornell_dir() + "/p.json");
            ADD_FAILURE() << "no error for " << (c.portals ? c.portals : "65 portals");
        } catch (const Error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    }
}

}  // namespace
}  // namespace pv
