// tests/test_adaptive.cpp: adaptive sampling and the stratified sample-count schedule (core/adaptive.h, issue 13).
#include <gtest/gtest.h>

#include "core/adaptive.h"
#include "core/renderer.h"
#include "support/scenes.h"
#include "support/stats.h"

namespace pv {
namespace {

TEST(AdaptiveSchedule, CheckpointsArePowersOfTwoAndThreeTimesPowers) {
    const uint32_t expected[] = {1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256};
    std::vector<uint32_t> got;
    for (uint32_t n = 0; n <= 256; ++n)
        if (is_adaptive_checkpoint(n)) got.push_back(n);
    EXPECT_EQ(got, std::vector<uint32_t>(std::begin(expected), std::end(expected)));
    EXPECT_TRUE(is_adaptive_checkpoint(3u << 30));
}

// A diffuse quad under a constant sky over half of the view, the bare sky (zero variance) over the other half.
struct HalfScene {
    std::shared_ptr<Scene> scene = std::make_shared<Scene>();
    CameraDesc camera;
    HalfScene() {
        Material m;
        m.bsdf = Lambertian{vec3(0.7f)};
        const uint32_t id = test::add_material(*scene, m);
        test::add_quad(*scene, vec3(-2.f, -2.f, 0.f), vec3(0.f, -2.f, 0.f), vec3(0.f, 2.f, 0.f), vec3(-2.f, 2.f, 0.f),
                       id);
        scene->environment.background = vec3(1.f);
        camera.eye = vec3(0.f, 0.f, 2.f);
        camera.target = vec3(0.f);
        camera.vfov_deg = 60.f;  // the quad fills the left half of the image (x < 0)
    }
};

TEST(Adaptive, ZeroVariancePixelsStopAtMinSppNoisyOnesLater) {
    HalfScene hs;
    Renderer r(hs.scene, 2);
    AdaptiveSettings a;
    a.noise_threshold = 0.02f;
    a.min_spp = 8;
    r.set_adaptive(a);
    RenderSettings s;
    s.sampler = SamplerKind::Independent;
    const int w = 32, h = 16;
    r.restart(hs.camera, s, w, h);
    while (!r.converged() && r.stats().spp < 4096) r.render_pass();
    ASSERT_TRUE(r.converged()) << r.adaptive_mask().active_count() << " pixels still active";
    uint32_t quad_min = ~0u;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint32_t n = r.film().pixel(x, y).n;
            ASSERT_TRUE(is_adaptive_checkpoint(n)) << x << "," << y << ": " << n;
            ASSERT_GE(n, a.min_spp);
            if (x >= w / 2 + 3) {
                EXPECT_EQ(n, a.min_spp) << x << "," << y;  // the sky, beyond the filter radius
            }
            if (x < w / 2 - 3) quad_min = std::min(quad_min, n);
        }
    // The quad's relative error at min_spp: about sqrt(var / n) / mean > 0.02 for this variance.
    EXPECT_GT(quad_min, a.min_spp);
    // Below the threshold on the quad, measured against the exact radiance: albedo x sky = 0.7.
    double rel_mse = 0.0;
    int count = 0;
    for (int y = 2; y < h - 2; ++y)
        for (int x = 2; x < w / 2 - 3; ++x) {
            const vec3 m = r.film().mean().at(x, y);
            rel_mse += double((m.x - 0.7f) * (m.x - 0.7f)) / (0.49 + 0.01);
            ++count;
        }
    EXPECT_LT(std::sqrt(rel_mse / count), 1.5 * a.noise_threshold);
}

// Stopping on the samples themselves biases a pixel slightly (one that happened to look converged stops). The
// bias must stay below the noise: the total mean of adaptive renders over many seeds agrees with non-adaptive ones
// within |z| < 3.29, on the Cornell box (independent samples, for the i.i.d. variance).
TEST(Adaptive, BiasBelowTheNoiseOnTheCornellBox) {
    const auto scene = test::cornell_box();
    const int w = 24, h = 24;
    test::Moments adaptive, plain;
    for (uint32_t seed = 0; seed < 8; ++seed) {
        RenderSettings s;
        s.sampler = SamplerKind::Independent;
        s.seed = 1000 + seed;
        Renderer r(scene, 2);
        AdaptiveSettings a;
        a.noise_threshold = 0.05f;
        a.min_spp = 8;
        r.set_adaptive(a);
        r.restart(scene->camera, s, w, h);
        while (!r.converged() && r.stats().spp < 1024) r.render_pass();
        const test::PixelStats st = test::PixelStats::from_film(r.film());
        adaptive.add(st.total_mean());
        s.seed = 2000 + seed;
        const test::PixelStats ps =
            test::PixelStats::from_film(test::render_with_renderer(scene, scene->camera, s, w, h, 128));
        plain.add(ps.total_mean());
    }
    const double z = (adaptive.mean - plain.mean) /
                     std::sqrt(adaptive.variance() / double(adaptive.n) + plain.variance() / double(plain.n));
    EXPECT_LT(std::fabs(z), 3.29) << adaptive.mean << " vs " << plain.mean;
}

}  // namespace
}  // namespace pv
