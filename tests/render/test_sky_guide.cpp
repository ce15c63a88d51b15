// tests/render/test_sky_guide.cpp: the learned sky distribution for next-event estimation (core/render/sky_guide.h):
// its sampling against its pdf (chi-square) alone and inside the environment's mixture, the guided and unguided images
// of a room lit through a window agreeing within a confidence interval from the sample variance, a white furnace
// under a constant sky, determinism (threads, resumed shards), where it applies, and that it concentrates: guided
// sky samples pass the window far more often than the sky's own.
// Test kinds: unit; statistical: SkyGuideSampling; analytic: SkyGuideFurnace
#include <gtest/gtest.h>

#include "core/frame/renderer.h"
#include "core/partial/partial.h"
#include "core/render/sky_guide_training.h"
#include "tests/support/chi2.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

// A closed box [0,2] x [0,1] x [0,1] with a square skylight 0.4 x 0.4 in its ceiling (x in 1.3..1.7, z in
// 0.3..0.7), lit by a constant sky and optionally a wide sun straight through the skylight. Camera inside.
std::shared_ptr<Scene> skylight_room(bool sun) {
    auto scene = std::make_shared<Scene>();
    Material wall;
    wall.bsdf = Lambertian{vec3(0.7f)};
    const uint32_t m = test::add_material(*scene, wall);
    // Inward-facing walls (floor, four sides), then the ceiling y = 1 around the hole in four strips.
    test::add_quad(*scene, vec3(0, 0, 0), vec3(0, 0, 1), vec3(2, 0, 1), vec3(2, 0, 0), m);
    test::add_quad(*scene, vec3(0, 0, 0), vec3(2, 0, 0), vec3(2, 1, 0), vec3(0, 1, 0), m);
    test::add_quad(*scene, vec3(0, 0, 1), vec3(0, 1, 1), vec3(2, 1, 1), vec3(2, 0, 1), m);
    test::add_quad(*scene, vec3(0, 0, 0), vec3(0, 1, 0), vec3(0, 1, 1), vec3(0, 0, 1), m);
    test::add_quad(*scene, vec3(2, 0, 0), vec3(2, 0, 1), vec3(2, 1, 1), vec3(2, 1, 0), m);
    const float x0 = 1.3f, x1 = 1.7f, z0 = 0.3f, z1 = 0.7f;
    test::add_quad(*scene, vec3(0, 1, 0), vec3(x0, 1, 0), vec3(x0, 1, 1), vec3(0, 1, 1), m);
    test::add_quad(*scene, vec3(x1, 1, 0), vec3(2, 1, 0), vec3(2, 1, 1), vec3(x1, 1, 1), m);
    test::add_quad(*scene, vec3(x0, 1, 0), vec3(x1, 1, 0), vec3(x1, 1, z0), vec3(x0, 1, z0), m);
    test::add_quad(*scene, vec3(x0, 1, z1), vec3(x1, 1, z1), vec3(x1, 1, 1), vec3(x0, 1, 1), m);
    scene->environment.background = vec3(0.9f, 1.f, 1.1f);
    if (sun) {
        scene->environment.sun_direction = vec3(0.1f, 1.f, 0.05f);
        scene->environment.sun_angular_radius_deg = 6.f;
        scene->environment.sun_irradiance = vec3(3.f);
    }
    scene->camera.eye = vec3(0.2f, 0.5f, 0.5f);
    scene->camera.target = vec3(1.5f, 0.4f, 0.5f);
    scene->camera.vfov_deg = 80.f;
    return scene;
}

RenderSettings independent(uint32_t seed, bool guide) {
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // the bounds use the i.i.d. sample variance
    s.seed = seed;
    s.sky_guide = guide ? SkyGuideMode::On : SkyGuideMode::Off;
    return s;
}

// The guide the Renderer would train for this scene, camera and settings.
std::shared_ptr<const SkyGuide> trained(const TraceableScene& ts, const RenderSettings& s, int w, int h) {
    return train_sky_guide(ts, s, Camera(ts.scene().camera, w, h));
}

// A synthetic guide over two cells (x < 1, x >= 1 of [0,2]^3): smooth weights, a bright spot, and zero bands.
std::shared_ptr<const SkyGuide> synthetic_guide() {
    const SkyGuideGrid grid(glm::ivec3(2, 1, 1), vec3(0.f), vec3(2.f));
    std::vector<double> w(size_t(2 * SkyGuide::kBins), 0.0);
    for (int c = 0; c < 2; ++c)
        for (int i = 0; i < SkyGuide::kBins; ++i) {
            const int band = i / SkyGuide::kColumns;
            if (band == 2 + c) continue;  // a band never seen in this cell
            w[size_t(c * SkyGuide::kBins + i)] = 1.0 + double((i * 7 + c * 13) % 11) + (i == 40 + 9 * c ? 500.0 : 0.0);
        }
    return std::make_shared<SkyGuide>(w, grid);
}

TEST(SkyGuideSampling, SamplesFollowTheirPdfInEveryCell) {
    const auto guide = synthetic_guide();
    ASSERT_TRUE(guide->valid());
    for (const vec3 p : {vec3(0.5f, 1.f, 1.f), vec3(1.5f, 0.2f, 1.9f)}) {
        test::Chi2Options o;
        o.sample_count = 300000;
        o.test_count = 2;
        const auto r = test::chi2_test(
            [&](Pcg32& g) -> std::optional<vec3> {
                const float ub = g.next_float();
                const float u0 = g.next_float();
                return guide->sample(p, ub, vec2(u0, g.next_float()));
            },
            [&](vec3 w) { return double(guide->pdf(p, w)); }, o);
        EXPECT_TRUE(r.passed) << r.message;
        EXPECT_NEAR(r.pdf_integral, 1.0, 1e-2) << r.message;
    }
    // Bin probabilities times the bin solid angle: each cell's pdf integrates to exactly 1 (up to float sums).
    for (int c = 0; c < 2; ++c) {
        double total = 0.0;
        for (int i = 0; i < SkyGuide::kBins; ++i) total += double(guide->probability(c, i));
        EXPECT_NEAR(total, 1.0, 1e-5);
    }
}

TEST(SkyGuide, NoWeightGivesAnInvalidGuide) {
    const SkyGuideGrid grid(glm::ivec3(1), vec3(0.f), vec3(1.f));
    EXPECT_FALSE(SkyGuide(std::vector<double>(size_t(SkyGuide::kBins), 0.0), grid).valid());
    EXPECT_FALSE(SkyGuide(std::vector<double>(3, 1.0), grid).valid());  // wrong size
    std::vector<double> nan(size_t(SkyGuide::kBins), std::nan(""));
    EXPECT_FALSE(SkyGuide(nan, grid).valid());
}

// Every direction (poles, the phi seam, non-finite) has a bin and every point (outside the grid, NaN) a cell.
TEST(SkyGuide, BinAndCellStayInRange) {
    const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
    for (const vec3 d : {vec3(0, 1, 0), vec3(0, -1, 0), vec3(1, 0, 0), vec3(1, 0, -0.f), vec3(1, 0, 1e-30f),
                         vec3(nan, 0, 0), vec3(0, nan, 0), vec3(inf, 0, 0)}) {
        const int b = SkyGuide::bin(d);
        EXPECT_GE(b, 0);
        EXPECT_LT(b, SkyGuide::kBins);
    }
    EXPECT_EQ(SkyGuide::bin(vec3(0, 1, 0)) / SkyGuide::kColumns, 0);                      // zenith: top band
    EXPECT_EQ(SkyGuide::bin(vec3(0, -1, 0)) / SkyGuide::kColumns, SkyGuide::kBands - 1);  // nadir: bottom band
    const SkyGuideGrid grid(glm::ivec3(2, 3, 4), vec3(0.f), vec3(1.f));
    for (const vec3 p : {vec3(-5.f), vec3(5.f), vec3(nan), vec3(0.999999f), vec3(inf, -inf, 0.5f)}) {
        const int c = grid.cell(p);
        EXPECT_GE(c, 0);
        EXPECT_LT(c, grid.cells());
    }
    EXPECT_EQ(grid.cell(vec3(0.9f, 0.9f, 0.9f)), grid.cells() - 1);
}

// The environment's whole sample (sun, sky and guide mixed) follows light_pdf_escape, the sample's own pdf is that
// value, and it integrates to 1.
TEST(SkyGuideSampling, EnvironmentMixtureFollowsItsPdf) {
    TraceableScene ts(skylight_room(true));
    ts.set_sky_guide(synthetic_guide());
    ASSERT_EQ(ts.sky_guide_probability(), TraceableScene::kSkyGuideProbability);
    EXPECT_TRUE(ts.light_selection_draw());
    for (const vec3 ref : {vec3(0.4f, 0.45f, 0.55f), vec3(1.5f, 0.2f, 0.5f)})
        test::expect_environment_samples_follow_pdf(ts, ref);
}

TEST(SkyGuide, AppliesOnlyWhereTheSkyShinesWithNeeAndWithoutPortals) {
    const RenderSettings on = independent(0, true);
    EXPECT_TRUE(sky_guide_applies(TraceableScene(skylight_room(false)), on));
    EXPECT_FALSE(sky_guide_applies(TraceableScene(skylight_room(false)), independent(0, false)));
    RenderSettings no_nee = on;
    no_nee.light_sampling = false;
    EXPECT_FALSE(sky_guide_applies(TraceableScene(skylight_room(false)), no_nee));
    EXPECT_FALSE(sky_guide_applies(TraceableScene(test::cornell_box()), on));  // no environment
    auto sun_only = skylight_room(true);
    sun_only->environment.background = vec3(0.f);
    EXPECT_FALSE(sky_guide_applies(TraceableScene(sun_only), on));
    auto portal = skylight_room(false);
    portal->portals.push_back(Portal{vec3(1.3f, 1.f, 0.3f), vec3(0.f, 0.f, 0.4f), vec3(0.4f, 0.f, 0.f)});
    EXPECT_FALSE(sky_guide_applies(TraceableScene(portal), on));
    EXPECT_EQ(trained(TraceableScene(test::cornell_box()), on, 16, 16), nullptr);
}

// Settings strings: " sky_guide=on" only where the guide changes the image, and they parse back.
TEST(SkyGuide, SettingsStringMarksOnlyGuidedRenders) {
    const RenderSettings on = independent(3, true);
    EXPECT_NE(on.describe().find(" sky_guide=on"), std::string::npos);
    EXPECT_EQ(independent(3, false).describe().find("sky_guide"), std::string::npos);
    EXPECT_EQ(parse_settings(on.describe(), "t"), on);
    EXPECT_EQ(parse_settings(independent(3, false).describe(), "t"), independent(3, false));
    Renderer cornell(test::cornell_box(), 1);
    cornell.restart(test::cornell_box()->camera, on, 8, 8);
    EXPECT_EQ(cornell.settings_as_rendered().sky_guide,
              SkyGuideMode::Off);  // not applicable: the string from before the guide
    Renderer room(skylight_room(false), 1);
    room.restart(room.scene().camera, on, 8, 8);
    EXPECT_EQ(room.settings_as_rendered().sky_guide, SkyGuideMode::On);
}

test::PixelStats render_stats(std::shared_ptr<const Scene> scene, uint32_t seed, bool guide, int spp) {
    const CameraDesc cam = scene->camera;
    return test::PixelStats::from_film(
        test::render_with_renderer(std::move(scene), cam, independent(seed, guide), 12, 12, spp, 2));
}

// Guided and unguided renders of the skylit room (with and without a sun) agree per pixel (Welch t, Sidak) and in
// total (z); the guided one is less noisy.
TEST(SkyGuideSampling, GuidedRenderAgreesWithUnguided) {
    for (const bool sun : {false, true}) {
        const int spp = 256;
        const auto off = render_stats(skylight_room(sun), 3, false, spp);
        const auto on = render_stats(skylight_room(sun), 4, true, spp);
        const auto c = test::compare_images(off, on);
        EXPECT_TRUE(c.passed) << (sun ? "sun: " : "sky: ") << c.describe();
        EXPECT_LT(on.total_mean_variance(), off.total_mean_variance()) << (sun ? "sun" : "sky");
    }
}

// White furnace: a Lambertian sphere (rho = 0.5) under a constant sky L returns rho L at every point; guided, with
// NEE and MIS on, the mean over the samples that hit it is within 4 standard errors of that.
TEST(SkyGuideFurnace, WhiteFurnaceIsUnbiased) {
    auto scene = std::make_shared<Scene>();
    Material m;
    m.bsdf = Lambertian{vec3(0.5f)};
    test::add_icosphere(*scene, vec3(0.f), 1.f, 3, test::add_material(*scene, m));
    scene->environment.background = vec3(1.f);
    scene->camera.eye = vec3(0.3f, 0.4f, 3.5f);
    scene->camera.target = vec3(0.f);
    scene->camera.vfov_deg = 35.f;
    test::Tracer tracer(scene);
    const RenderSettings s = independent(11, true);
    const auto guide = trained(tracer, s, 16, 16);
    ASSERT_NE(guide, nullptr);
    tracer.set_sky_guide(guide);
    ASSERT_GT(tracer.sky_guide_probability(), 0.f);
    const Camera camera(scene->camera, 16, 16);
    test::Moments mom;
    Sampler sampler(s.seed, s.sampler);
    tracer.for_each_sample(scene->camera, s, 16, 16, 64, [&](int x, int y, uint32_t i, vec3 v) {
        Hit hit;
        if (tracer.accel().intersect(camera_ray(camera, sampler, x, y, i), hit)) mom.add(double(v.x));
    });
    ASSERT_GT(mom.n, 1000u);
    EXPECT_NEAR(mom.mean, 0.5, 4.0 * mom.stderr_of_mean());
}

bool same_pixels(const Film& a, const Film& b) {
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const FilmPixel &p = a.pixel(x, y), &q = b.pixel(x, y);
            if (p.n != q.n) return false;
            for (int c = 0; c < 3; ++c)
                if (p.sum[c] != q.sum[c] || p.sum_sq[c] != q.sum_sq[c]) return false;
        }
    return true;
}

Film render_passes(Renderer& r, const RenderSettings& s, int passes) {
    r.restart(r.scene().camera, s, 12, 10);
    for (int i = 0; i < passes; ++i) r.render_pass();
    return r.film();
}

// The guided image is bit-identical for 1, 2 and 4 threads, and a render resumed at sample 4 (a new restart, so a
// newly trained guide) adds exactly the whole render's last passes.
TEST(SkyGuide, DeterministicForThreadsAndShards) {
    const auto scene = skylight_room(true);
    const RenderSettings s = independent(5, true);
    Renderer r1(scene, 1), r2(scene, 2), r4(scene, 4);
    const Film f1 = render_passes(r1, s, 6);
    EXPECT_GT(r1.stats().guide_seconds, 0.0);
    EXPECT_TRUE(same_pixels(f1, render_passes(r2, s, 6)));
    EXPECT_TRUE(same_pixels(f1, render_passes(r4, s, 6)));
    const Film first = render_passes(r2, s, 4);
    r2.restart(scene->camera, s, 12, 10);
    r2.load_film(first);
    r2.set_next_sample(4);
    for (int i = 0; i < 2; ++i) r2.render_pass();
    EXPECT_TRUE(same_pixels(f1, r2.film()));
    // And the guide changes the image (the comparison above is not vacuous).
    Renderer off(scene, 2);
    EXPECT_FALSE(same_pixels(f1, render_passes(off, independent(5, false), 6)));
}

// The guide concentrates: from points on the floor, directions drawn from the trained guide leave through the
// skylight much more often than the sky's own (uniform) directions, which pass with probability about the
// skylight's solid angle over 4 pi (at most 0.1 here). Bound: the guided fraction exceeds 4x the uniform one by more
// than 4 standard errors of the difference.
TEST(SkyGuideSampling, GuidedSamplesPassTheOpeningFarMoreOften) {
    const TraceableScene ts(skylight_room(false));
    const RenderSettings s = independent(2, true);
    const auto guide = trained(ts, s, 32, 24);
    ASSERT_NE(guide, nullptr);
    Pcg32 rng(7, 9);
    const int n = 40000;
    int pass_guided = 0, pass_uniform = 0;
    for (int i = 0; i < n; ++i) {
        const vec3 p(0.1f + 1.8f * rng.next_float(), 1e-3f, 0.1f + 0.8f * rng.next_float());
        const float ub = rng.next_float();
        const float u0 = rng.next_float();
        const vec3 wg = guide->sample(p, ub, vec2(u0, rng.next_float()));
        const float v0 = rng.next_float();
        const std::optional<EnvironmentSample> es = ts.environment().sample(vec2(v0, rng.next_float()));
        ASSERT_TRUE(es.has_value());
        for (const auto& [w, count] : {std::pair{wg, &pass_guided}, std::pair{es->wi, &pass_uniform}}) {
            Ray ray;
            ray.o = p;
            ray.d = w;
            ray.tmax = std::numeric_limits<float>::infinity();
            if (w.y > 0.f && !ts.occluded(ray)) ++*count;
        }
    }
    const double fg = double(pass_guided) / n, fu = double(pass_uniform) / n;
    const double se = std::sqrt(fg * (1.0 - fg) / n + 16.0 * fu * (1.0 - fu) / n);
    EXPECT_GT(fg - 4.0 * fu, 4.0 * se) << "guided " << fg << ", uniform " << fu;
}

}  // namespace
}  // namespace pv

namespace pv {
namespace {

RenderSettings automatic(uint32_t seed) {
    RenderSettings s = independent(seed, true);
    s.sky_guide = SkyGuideMode::Auto;
    return s;
}

// The skylit room with the sun ten times as bright: it carries most of the light through the opening.
std::shared_ptr<Scene> sunny_room() {
    auto scene = skylight_room(true);
    scene->environment.sun_irradiance = vec3(30.f);
    return scene;
}

// --sky-guide auto: the training predicts a large cut of the variance in the room lit through a small skylight by
// the sky alone (the sky's own samples mostly end on the ceiling), and none worth the guide's cost where a sun
// through the same opening carries most of the light; the decision follows the rule (variance_ratio x cost < 1).
TEST(SkyGuide, AutoUsesTheGuideOnlyWhereItPays) {
    const RenderSettings s = automatic(1);
    const TraceableScene sky(skylight_room(false)), sun(sunny_room());
    const SkyGuideTraining a = train_sky_guide_judged(sky, s, Camera(sky.scene().camera, 48, 32));
    ASSERT_NE(a.guide, nullptr);
    EXPECT_TRUE(a.use);
    EXPECT_LT(a.variance_ratio * kSkyGuideRelativeCost, 1.0);
    EXPECT_GT(a.sky_share, 0.5);  // the sky lights this room
    const SkyGuideTraining b = train_sky_guide_judged(sun, s, Camera(sun.scene().camera, 48, 32));
    ASSERT_NE(b.guide, nullptr);  // trained, and learned something, but not used
    EXPECT_FALSE(b.use);
    EXPECT_GE(b.variance_ratio * kSkyGuideRelativeCost, 1.0);
    EXPECT_GT(b.sun_share, 0.5);
}

// Auto renders the image of `on` where it uses the guide and that of `off` where not, bit for bit, for 1, 2 and 4
// threads (the decision comes from the same deterministic training), and the settings string says which: auto
// until the first pass has decided, then " sky_guide=on" or nothing.
TEST(SkyGuide, AutoIsOnOrOffBitForBitForAnyThreadCount) {
    for (const bool sunny : {false, true}) {
        const auto scene = sunny ? sunny_room() : skylight_room(false);
        Renderer r1(scene, 1), r2(scene, 2), r4(scene, 4);
        r1.restart(scene->camera, automatic(5), 12, 10);
        EXPECT_NE(r1.settings_as_rendered().describe().find(" sky_guide=auto"), std::string::npos);
        const Film f1 = render_passes(r1, automatic(5), 3);
        EXPECT_EQ(r1.stats().guide_used, !sunny);
        EXPECT_EQ(r1.settings_as_rendered().sky_guide, sunny ? SkyGuideMode::Off : SkyGuideMode::On);
        EXPECT_TRUE(same_pixels(f1, render_passes(r2, automatic(5), 3)));
        EXPECT_TRUE(same_pixels(f1, render_passes(r4, automatic(5), 3)));
        EXPECT_EQ(r1.stats().guide_variance_ratio, r2.stats().guide_variance_ratio);
        EXPECT_EQ(r1.stats().guide_variance_ratio, r4.stats().guide_variance_ratio);
        EXPECT_TRUE(same_pixels(f1, render_passes(r2, independent(5, !sunny), 3)));
        EXPECT_FALSE(same_pixels(f1, render_passes(r2, independent(5, sunny), 3)));
    }
    EXPECT_EQ(parse_settings(automatic(2).describe(), "t"), automatic(2));
}

}  // namespace
}  // namespace pv

namespace pv {
namespace {

// The packed table realises DiscreteDistribution's exact probabilities: over all 2^23 values of k = floor(u 2^23),
// bin b is picked for exactly probability(cell, b) 2^23 of them (the direction taken at the bin's centre, where
// bin() cannot round to a neighbour), in both cells of the synthetic guide.
TEST(SkyGuide, PackedTablePicksEachBinWithItsExactProbability) {
    const auto guide = synthetic_guide();
    ASSERT_TRUE(guide->valid());
    const uint32_t n = 1u << DiscreteDistribution::kBits;
    for (int cell = 0; cell < 2; ++cell) {
        std::vector<uint32_t> count(size_t(SkyGuide::kBins), 0);
        for (uint32_t k = 0; k < n; ++k)
            ++count[size_t(SkyGuide::bin(guide->sample_in(cell, float(k) * 0x1p-23f, vec2(0.5f))))];
        for (int b = 0; b < SkyGuide::kBins; ++b)
            EXPECT_EQ(double(count[size_t(b)]), double(guide->probability(cell, b)) * double(n))
                << "cell " << cell << " bin " << b;
    }
}

// The viewer keeps the trained guide (and auto's decision) across restarts that change only the camera or the size:
// no training delays the first pass while the user orbits. New settings or materials retrain; a plain Renderer
// retrains at every restart.
TEST(SkyGuide, KeptAcrossCameraMovesOnlyWhenAsked) {
    const auto scene = skylight_room(false);
    for (const bool keep : {true, false}) {
        Renderer r(scene, 2);
        r.set_keep_sky_guide(keep);
        RenderSettings s = independent(9, true);
        s.sky_guide = SkyGuideMode::Auto;
        r.restart(scene->camera, s, 24, 16);
        r.render_pass();
        ASSERT_GT(r.stats().guide_seconds, 0.0);
        ASSERT_TRUE(r.stats().guide_used);
        const SkyGuide* first = r.traceable().sky_guide();
        CameraDesc moved = scene->camera;
        moved.eye += vec3(0.1f, 0.f, 0.f);
        r.restart(moved, s, 32, 20);
        r.render_pass();
        EXPECT_EQ(r.stats().guide_seconds > 0.0, !keep);  // trained again only without keep
        EXPECT_TRUE(r.stats().guide_used);
        EXPECT_EQ(r.settings_as_rendered().sky_guide, SkyGuideMode::On);
        if (!keep) continue;
        EXPECT_EQ(r.traceable().sky_guide(), first);  // the very same guide
        r.set_materials(r.traceable().materials());   // an edit, even to the same values
        r.restart(moved, s, 32, 20);
        r.render_pass();
        EXPECT_GT(r.stats().guide_seconds, 0.0);
        s.seed = 10;  // new settings
        r.restart(moved, s, 32, 20);
        r.render_pass();
        EXPECT_GT(r.stats().guide_seconds, 0.0);
    }
}

// What the viewer shows under the sky-guide drop-down: the decision auto took, with its prediction.
TEST(SkyGuide, StatusSaysWhatTheGuideDoes) {
    const auto room = skylight_room(false), sunny = sunny_room();
    Renderer r(room, 2);
    r.restart(room->camera, automatic(3), 24, 16);
    EXPECT_EQ(r.sky_guide_status(), "training in the first pass");
    r.render_pass();
    EXPECT_EQ(r.sky_guide_status().rfind("on (auto: variance x", 0), 0u) << r.sky_guide_status();
    Renderer q(sunny, 2);
    q.restart(sunny->camera, automatic(3), 24, 16);
    q.render_pass();
    EXPECT_EQ(q.sky_guide_status().rfind("off (auto: variance x", 0), 0u) << q.sky_guide_status();
    RenderSettings off = automatic(3);
    off.sky_guide = SkyGuideMode::Off;
    q.restart(sunny->camera, off, 24, 16);
    q.render_pass();
    EXPECT_EQ(q.sky_guide_status(), "");
    RenderSettings no_nee = automatic(3);
    no_nee.light_sampling = false;
    q.restart(sunny->camera, no_nee, 24, 16);
    EXPECT_EQ(q.sky_guide_status(), "not applicable");
}

}  // namespace
}  // namespace pv
