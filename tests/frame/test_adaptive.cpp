// tests/frame/test_adaptive.cpp: adaptive sampling (the noise threshold, and allocation: AdaptiveSettings::allocate)
// and the stratified sample-count schedule (core/frame/adaptive.h, issue 13).
// Test kinds: unit; statistical: AdaptiveStoppingBias AdaptiveAllocationBias
#include <gtest/gtest.h>

#include <cstring>
#include <map>

#include "core/frame/adaptive.h"
#include "core/frame/renderer.h"
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
// Total means of 8 seeds' adaptive renders of the Cornell box (24x24, independent samples, for the i.i.d. variance;
// `passes` passes at most, fewer once every pixel has stopped) against 8 plain renders of `plain_spp`: the z of their
// difference. `max_mean_count` receives the largest mean samples per pixel among the adaptive renders.
double cornell_bias_z(const AdaptiveSettings& a, uint32_t seed_base, uint32_t passes, int plain_spp,
                      double* max_mean_count = nullptr) {
    const auto scene = test::cornell_box();
    const int w = 24, h = 24;
    test::Moments adaptive, plain;
    for (uint32_t seed = 0; seed < 8; ++seed) {
        RenderSettings s;
        s.sampler = SamplerKind::Independent;
        s.seed = seed_base + seed;
        Renderer r(scene, 2);
        r.set_adaptive(a);
        r.restart(scene->camera, s, w, h);
        while (!r.converged() && r.stats().spp < passes) r.render_pass();
        if (max_mean_count) *max_mean_count = std::max(*max_mean_count, r.film().mean_count());
        adaptive.add(test::PixelStats::from_film(r.film()).total_mean());
        s.seed = seed_base + 1000 + seed;
        plain.add(test::PixelStats::from_film(test::render_with_renderer(scene, scene->camera, s, w, h, plain_spp))
                      .total_mean());
    }
    return (adaptive.mean - plain.mean) /
           std::sqrt(adaptive.variance() / double(adaptive.n) + plain.variance() / double(plain.n));
}

TEST(AdaptiveStoppingBias, BiasBelowTheNoiseOnTheCornellBox) {
    AdaptiveSettings a;
    a.noise_threshold = 0.05f;
    a.min_spp = 8;
    EXPECT_LT(std::fabs(cornell_bias_z(a, 1000, 1024, 128)), 3.29);
}

// Allocation: each pixel takes samples in proportion to its relative error per sample over the root of its cost.
AdaptiveSettings allocating(uint32_t min_spp) {
    AdaptiveSettings a;
    a.allocate = true;
    a.min_spp = min_spp;
    return a;
}

// Allocation's passes: pilot passes 1..8 and every 8th after (each pixel a sample), main passes between.
uint32_t pilot_passes(uint32_t passes) {
    uint32_t n = 0;
    for (uint32_t p = 1; p <= passes; ++p) n += is_pilot_pass(p) ? 1u : 0u;
    return n;
}

// The noiseless sky settles at the floor rate, exactly: after Q main passes a pixel of weight w has ceil(Q w) main
// samples (plus one per pilot pass). The noisy quad keeps the full rate, and both stay unbiased (the sky exactly 1,
// the quad 0.7 within its noise).
TEST(AdaptiveAllocation, NoiselessPixelsTakeTheFloorRateNoisyOnesEveryPass) {
    HalfScene hs;
    Renderer r(hs.scene, 2);
    r.set_adaptive(allocating(8));
    RenderSettings s;
    s.sampler = SamplerKind::Independent;
    const int w = 32, h = 16, passes = 64;
    r.restart(hs.camera, s, w, h);
    for (int i = 0; i < passes; ++i) r.render_pass();
    const uint32_t pilots = pilot_passes(passes), mains = passes - pilots;
    EXPECT_EQ(pilots, 15u);  // 1..8, 16, 24, ..., 64
    const uint32_t floor_count = uint32_t(std::ceil(double(mains) * double(kAllocationFloor)));
    uint32_t quad_min = ~0u, image_max = 0;
    double quad_sum = 0.0, quad_var = 0.0;
    int quad_pixels = 0;
    const test::PixelStats st = test::PixelStats::from_film(r.film());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const FilmPixel& px = r.main_film().pixel(x, y);
            EXPECT_EQ(r.pilot_film().pixel(x, y).n, pilots);
            EXPECT_EQ(r.film().pixel(x, y).n, px.n + pilots);
            image_max = std::max(image_max, px.n);
            if (x >= w / 2 + 3) {  // the sky beyond the 5x5 filter's reach
                EXPECT_EQ(px.n, floor_count) << x << "," << y;
                EXPECT_FLOAT_EQ(r.film().mean().at(x, y).x, 1.f);
                EXPECT_FLOAT_EQ(r.adaptive_mask().weight(x, y), kAllocationFloor);
            }
            if (x >= 3 && x < w / 2 - 3 && y >= 3 && y < h - 3) {  // the quad, away from its edges
                quad_min = std::min(quad_min, px.n);
                const size_t i = (size_t(y) * size_t(w) + size_t(x)) * 3;
                quad_sum += st.mean[i];
                quad_var += st.var_mean[i];
                ++quad_pixels;
            }
        }
    // The noisiest pixels (the quad's edge) at nearly the full rate (a pixel whose weight rises after a pilot pass
    // does not catch up on the passes it skipped); the whole quad well above the sky (its weights are estimates of
    // one relative error, each from 25 pixels' pilot half buffers).
    EXPECT_GE(image_max, mains - 8);
    EXPECT_GT(2 * quad_min, 3 * floor_count);  // at least 1.5x the floor (its weights are ~0.5 of the edge's)
    const double mean = quad_sum / quad_pixels, se = std::sqrt(quad_var) / quad_pixels;
    EXPECT_LT(std::fabs(mean - 0.7), 4.0 * se + 1e-6) << mean << " +- " << se;
    EXPECT_LT(r.main_film().mean_count(), 0.75 * mains);  // the sky half at a quarter
}

// A pixel's main samples are the indices 0 .. n-1 of its own count: its main sums are those a uniform render of n
// passes gives it, bit for bit (so Sobol's per-pixel stratification holds under any allocation); the pilot film is
// a uniform render of the pilot passes under the pilot seed.
TEST(AdaptiveAllocation, EachPixelTakesTheFirstIndicesOfItsOwnCount) {
    const auto scene = test::cornell_box();
    RenderSettings s;
    s.seed = 5;
    const int w = 20, h = 16, passes = 40;
    Renderer r(scene, 2);
    r.set_adaptive(allocating(4));
    r.restart(scene->camera, s, w, h);
    for (int i = 0; i < passes; ++i) r.render_pass();
    std::map<uint32_t, Film> uniform;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) uniform.emplace(r.main_film().pixel(x, y).n, Film());
    ASSERT_GE(uniform.size(), 3u) << "the allocation gave every pixel the same count";
    for (auto& [n, film] : uniform) film = test::render_with_renderer(scene, scene->camera, s, w, h, int(n));
    RenderSettings ps = s;
    ps.seed = pilot_seed(s.seed);
    const Film pilot = test::render_with_renderer(scene, scene->camera, ps, w, h, int(pilot_passes(passes)));
    auto expect_same = [](const FilmPixel& p, const FilmPixel& q, int x, int y) {
        ASSERT_EQ(p.n, q.n);
        ASSERT_EQ(p.n_even, q.n_even) << x << "," << y;
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(std::memcmp(&p.sum[c], &q.sum[c], sizeof(double)), 0) << x << "," << y << " n " << p.n;
            ASSERT_EQ(std::memcmp(&p.sum_even[c], &q.sum_even[c], sizeof(double)), 0) << x << "," << y;
        }
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const FilmPixel& p = r.main_film().pixel(x, y);
            expect_same(p, uniform.at(p.n).pixel(x, y), x, y);
            expect_same(r.pilot_film().pixel(x, y), pilot.pixel(x, y), x, y);
        }
}

// The image is the fixed-weight combination of the pilot's and the main film's means, pixel by pixel, and its
// half-buffer error estimate is that of the same combination of the films' halves (independent estimates).
TEST(AdaptiveAllocation, ImageCombinesPilotAndMainWithFixedWeights) {
    const auto scene = test::cornell_box();
    RenderSettings s;
    const int w = 16, h = 12, passes = 24;
    Renderer r(scene, 2);
    r.set_adaptive(allocating(16));
    r.restart(scene->camera, s, w, h);
    for (int i = 0; i < passes; ++i) r.render_pass();
    const double a = double(pilot_passes(passes)) / passes, b = 1.0 - a;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const FilmPixel &p = r.pilot_film().pixel(x, y), &m = r.main_film().pixel(x, y), &q = r.film().pixel(x, y);
            ASSERT_GT(m.n, 1u);
            const uint32_t po = p.n - p.n_even, mo = m.n - m.n_even;
            ASSERT_TRUE(po > 0 && mo > 0 && p.n_even > 0 && m.n_even > 0);
            double expected_err = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double mean = a * p.sum[c] / p.n + b * m.sum[c] / m.n;
                EXPECT_NEAR(q.sum[c] / q.n, mean, 1e-12 * (1.0 + mean));
                const double ha = a * p.sum_even[c] / p.n_even + b * m.sum_even[c] / m.n_even;
                const double hb = a * (p.sum[c] - p.sum_even[c]) / po + b * (m.sum[c] - m.sum_even[c]) / mo;
                expected_err += 0.25 * (ha - hb) * (ha - hb) / (mean * mean + 0.01) / 3.0;
            }
            const std::optional<double> e = pixel_rel_mse(q);
            ASSERT_TRUE(e.has_value());
            EXPECT_NEAR(*e, expected_err, 1e-9 * (1.0 + expected_err)) << x << "," << y;
        }
}

// The weights come from the samples, which biases the estimate slightly (as stopping does). The bias must stay
// below the noise: the total mean of allocating renders over 8 seeds agrees with uniform ones within |z| < 3.29,
// on the Cornell box (independent samples, for the i.i.d. variance).
TEST(AdaptiveAllocationBias, BiasBelowTheNoiseOnTheCornellBox) {
    double mean_count = 0.0;
    EXPECT_LT(std::fabs(cornell_bias_z(allocating(8), 3000, 128, 96, &mean_count)), 3.29);
    EXPECT_LT(mean_count, 120.0);  // the allocation did something
}

// Off, nothing changes: the film equals a render without adaptive settings, bit for bit.
TEST(AdaptiveAllocation, OffLeavesTheRenderAsItWas) {
    const auto scene = test::cornell_box();
    RenderSettings s;
    Renderer r(scene, 2);
    AdaptiveSettings a = allocating(4);
    a.allocate = false;
    r.set_adaptive(a);
    r.restart(scene->camera, s, 16, 12);
    for (int i = 0; i < 24; ++i) r.render_pass();
    const Film plain = test::render_with_renderer(scene, scene->camera, s, 16, 12, 24);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 16; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(std::memcmp(&r.film().pixel(x, y).sum[c], &plain.pixel(x, y).sum[c], sizeof(double)), 0);
}

}  // namespace
}  // namespace pv
