// tests/frame/test_progressive.cpp: the asynchronous driver's restart logic, without a window. Suites start with
// "Progressive" so they are part of the TSan subset. Small images keep each test well under a second.
// No test asserts that work finishes within a wall-clock interval (issue 26): each waits for an event (a pass
// published, a partial render made, a state reached) with kDeadline, long enough for a loaded sanitizer build;
// a deadline that passes is a hang, not slowness.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cstring>
#include <thread>

#include "core/denoise/denoise_nfor.h"
#include "core/frame/progressive.h"
#include "core/load/scene_file.h"
#include "core/partial/partial.h"

namespace pv {
namespace {

using namespace std::chrono_literals;

constexpr std::chrono::milliseconds kDeadline = 300s;
bool before_deadline(std::chrono::steady_clock::time_point start) {
    return std::chrono::steady_clock::now() - start < kDeadline;
}

// Render threads of the driver. Under sanitizers one: Debian's TBB is not instrumented, so TSan cannot see its
// synchronisation and would flag every pass; with one thread it checks what these tests are about, the driver
// thread against the caller's thread.
#ifdef PATHVIEW_SANITIZED
constexpr int kThreads = 1;
#else
constexpr int kThreads = 2;
#endif

std::shared_ptr<const Scene> cornell() {
    static const auto scene = std::make_shared<const Scene>(load_scene(builtin_scene_path()));
    return scene;
}

RenderRequest request(int w, int h, RenderSettings settings = {}) {
    RenderRequest r;
    r.camera = cornell()->camera;
    r.settings = settings;
    r.width = w;
    r.height = h;
    return r;
}

// The mean image of `passes` passes of a fresh synchronous Renderer.
std::vector<float> reference(const RenderRequest& req, int passes) {
    Renderer r(cornell(), 1);
    if (!req.materials.empty()) r.set_materials(req.materials);
    if (req.fog) r.set_fog(*req.fog);
    r.restart(req.camera, req.settings, req.width, req.height);
    for (int i = 0; i < passes; ++i) r.render_pass();
    return r.film().mean().rgb;
}

// Waits for generation g to reach min_spp and returns the latest snapshot (generation 0 on a timeout).
Snapshot settled(const ProgressiveRenderer& pr, uint64_t g, uint32_t min_spp) {
    Snapshot s;
    if (pr.wait_for(g, min_spp, kDeadline)) pr.latest(s);
    return s;
}

// Waits (polling) for the partial render asked for with request_partial(); nullopt at the deadline.
std::optional<PartialRender> wait_partial(ProgressiveRenderer& pr) {
    for (const auto start = std::chrono::steady_clock::now(); before_deadline(start);) {
        if (std::optional<PartialRender> p = pr.take_partial()) return p;
        std::this_thread::sleep_for(10ms);
    }
    return std::nullopt;
}

}  // namespace

TEST(ProgressiveRenderer, SettingsChangeRestartsAccumulation) {
    ProgressiveRenderer pr(cornell(), kThreads);
    const uint64_t g1 = pr.restart(request(32, 32));
    ASSERT_TRUE(pr.wait_for(g1, 3, kDeadline));
    RenderSettings changed;
    changed.max_depth = 2;
    const uint64_t g2 = pr.restart(request(32, 32, changed));
    EXPECT_GT(g2, g1);
    const Snapshot s = settled(pr, g2, 1);
    EXPECT_GE(s.generation, g2);
    EXPECT_EQ(s.settings, changed);
    EXPECT_GE(s.spp, 1u);
    EXPECT_EQ(s.width, 32);
}

TEST(ProgressiveRenderer, NoStaleSamplesAfterRestart) {
    // Render A at length, restart to B (other seed, depth and size) while passes of A are in flight, and stop B
    // at 3 spp: the published image must equal a fresh synchronous render of B bit for bit.
    ProgressiveRenderer pr(cornell(), kThreads);
    const uint64_t ga = pr.restart(request(48, 40));
    ASSERT_TRUE(pr.wait_for(ga, 2, kDeadline));
    RenderSettings b_settings;
    b_settings.seed = 7;
    b_settings.max_depth = 3;
    const RenderRequest b = request(40, 32, b_settings);
    pr.set_target(3, 0.0);
    const uint64_t gb = pr.restart(b);
    const Snapshot s = settled(pr, gb, 3);
    ASSERT_EQ(s.generation, gb);
    ASSERT_EQ(s.spp, 3u);
    EXPECT_TRUE(s.target_reached);
    const std::vector<float> ref = reference(b, 3);
    ASSERT_EQ(s.rgb.size(), ref.size());
    for (size_t i = 0; i < ref.size(); ++i) ASSERT_EQ(s.rgb[i], ref[i]) << "at float " << i;
    for (float n : s.samples) EXPECT_LE(n, 3.f);
}

TEST(ProgressiveRenderer, RapidRestartsKeepOnlyTheLastRequest) {
    // A burst of restarts (as from a camera drag): the surviving accumulation is the last one, sample-exact.
    ProgressiveRenderer pr(cornell(), kThreads);
    pr.set_target(2, 0.0);
    uint64_t last = 0;
    RenderRequest req = request(32, 32);
    for (int i = 0; i < 50; ++i) {
        req.camera.eye.x = 278.f + float(i);
        last = pr.restart(req);
    }
    const Snapshot s = settled(pr, last, 2);
    ASSERT_EQ(s.generation, last);
    EXPECT_EQ(s.rgb, reference(req, 2));
}

TEST(ProgressiveRenderer, MaterialChangeRestartsWithNewMaterials) {
    ProgressiveRenderer pr(cornell(), kThreads);
    RenderRequest req = request(24, 24);
    const uint64_t g1 = pr.restart(req);
    ASSERT_TRUE(pr.wait_for(g1, 1, kDeadline));
    req.materials = cornell()->materials;
    for (Material& m : req.materials)
        if (m.has_emission()) m.emission *= 2.f;
    pr.set_target(2, 0.0);
    const uint64_t g2 = pr.restart(req);
    const Snapshot s = settled(pr, g2, 2);
    ASSERT_EQ(s.generation, g2);
    EXPECT_EQ(s.rgb, reference(req, 2));
}

// The viewer's fog controls: a request's fog replaces the scene's (the image is the synchronous renderer's with that
// fog, and differs from the one without), and a later request without one keeps it.
TEST(ProgressiveRenderer, FogChangeRestartsWithTheNewFog) {
    ProgressiveRenderer pr(cornell(), kThreads);
    RenderRequest req = request(24, 24);
    pr.set_target(2, 0.0);
    const uint64_t g1 = pr.restart(req);
    const Snapshot clear = settled(pr, g1, 2);
    ASSERT_EQ(clear.generation, g1);
    req.fog = HomogeneousMedium{vec3(0.1f, 0.2f, 0.3f), vec3(0.3f), 0.2f};
    const uint64_t g2 = pr.restart(req);
    const Snapshot foggy = settled(pr, g2, 2);
    ASSERT_EQ(foggy.generation, g2);
    EXPECT_EQ(foggy.rgb, reference(req, 2));
    EXPECT_NE(foggy.rgb, clear.rgb);
    RenderRequest kept = req;
    kept.fog.reset();
    kept.settings.seed = 1;  // a restart that is not the fog's
    const uint64_t g3 = pr.restart(kept);
    const Snapshot s3 = settled(pr, g3, 2);
    ASSERT_EQ(s3.generation, g3);
    RenderRequest expected = kept;
    expected.fog = req.fog;
    EXPECT_EQ(s3.rgb, reference(expected, 2));
}

TEST(ProgressiveRenderer, SnapshotWhileRendering) {
    // Copies snapshots while the driver renders, until three new ones have been seen past 1 spp (events, not a
    // time window: a loaded machine only makes this take longer).
    ProgressiveRenderer pr(cornell(), kThreads);
    const uint64_t g = pr.restart(request(64, 64));
    Snapshot s;
    uint32_t last_spp = 0;
    uint64_t last_serial = 0;
    int copies = 0;
    const auto start = std::chrono::steady_clock::now();
    while ((copies < 3 || last_spp < 2) && before_deadline(start)) {
        if (pr.latest(s)) {
            ++copies;
            EXPECT_EQ(s.generation, g);
            EXPECT_GT(s.serial, last_serial);
            EXPECT_GE(s.spp, last_spp);
            ASSERT_EQ(s.rgb.size(), size_t(64 * 64 * 3));
            ASSERT_EQ(s.rel_error.size(), size_t(64 * 64));
            for (float v : s.rgb) ASSERT_TRUE(std::isfinite(v));
            last_spp = s.spp;
            last_serial = s.serial;
        }
        pr.wait_for(g, last_spp + 1, kDeadline);  // the next pass
    }
    EXPECT_GE(copies, 3);
    EXPECT_GE(last_spp, 2u);
    EXPECT_GT(s.mrays_per_s, 0.0);
    EXPECT_GT(s.rel_mse, 0.0);
}

TEST(ProgressiveRenderer, PauseStopsAndResumeContinues) {
    ProgressiveRenderer pr(cornell(), kThreads);
    const uint64_t g = pr.restart(request(32, 32));
    ASSERT_TRUE(pr.wait_for(g, 2, kDeadline));
    pr.set_paused(true);
    // The driver makes a requested partial render between passes: once it is made, the pass in flight (if any)
    // has landed and been published, and no other pass starts while paused.
    pr.request_partial();
    const std::optional<PartialRender> part = wait_partial(pr);
    ASSERT_TRUE(part);
    Snapshot a;
    pr.latest(a);
    EXPECT_EQ(a.spp, part->ranges.back().end());
    std::this_thread::sleep_for(100ms);  // a chance for a wrongly rendered pass to show; never a false failure
    Snapshot b = a;
    EXPECT_FALSE(pr.latest(b));
    pr.set_paused(false);
    EXPECT_TRUE(pr.wait_for(g, a.spp + 2, kDeadline));
}

TEST(ProgressiveRenderer, DestructorWhileRendering) {
    for (int i = 0; i < 3; ++i) {
        ProgressiveRenderer pr(cornell(), kThreads);
        pr.restart(request(256, 256));
        std::this_thread::sleep_for(std::chrono::milliseconds(5 * i));
    }
    ProgressiveRenderer idle(cornell(), kThreads);  // never started: the destructor joins an idle driver
}

// ---------------------------------------------------------------- the viewer's resumable snapshot
// request_partial(): the partial render (core/partial/partial.h) is made between passes (its film is exactly that of
// spp whole passes), also once rendering has stopped, and resuming it continues the accumulation bit for bit.

namespace {

// The film of passes [0, passes) of a fresh synchronous Renderer; with `from`, continued from that film.
Film reference_film(int passes, const Film* from = nullptr, uint32_t first = 0) {
    Renderer r(cornell(), 1);
    const RenderRequest req = request(24, 16);
    r.restart(req.camera, req.settings, req.width, req.height);
    if (from) r.load_film(*from);
    r.set_next_sample(first);
    for (int i = 0; i < passes; ++i) r.render_pass();
    return r.film();
}

bool same_pixels(const Film& a, const Film& b) {
    return a.width() == b.width() && a.height() == b.height() &&
           std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(FilmPixel)) == 0;
}

TEST(ProgressiveRenderer, StoppedAccumulationResumesBitForBit) {
    ProgressiveRenderer pr(cornell(), kThreads);
    pr.set_target(6, 0.0);
    const uint64_t g = pr.restart(request(24, 16));
    ASSERT_TRUE(pr.wait_for(g, 6, kDeadline));
    pr.request_partial();  // rendering has stopped at the target: the driver wakes for the request
    const std::optional<PartialRender> part = wait_partial(pr);
    ASSERT_TRUE(part);
    EXPECT_EQ(format_ranges(part->ranges), "0:6");
    EXPECT_TRUE(same_pixels(part->film, reference_film(6)));
    EXPECT_FALSE(pr.take_partial());  // handed over once
    // Resumed: 2 more passes from index 6 equal 8 passes.
    EXPECT_TRUE(same_pixels(reference_film(2, &part->film, 6), reference_film(8)));
}

TEST(ProgressiveRenderer, RunningAccumulationGivesWholePasses) {
    ProgressiveRenderer pr(cornell(), kThreads);
    const uint64_t g = pr.restart(request(24, 16));
    ASSERT_TRUE(pr.wait_for(g, 2, kDeadline));
    pr.request_partial();
    const std::optional<PartialRender> part = wait_partial(pr);
    ASSERT_TRUE(part);
    ASSERT_EQ(part->ranges.size(), 1u);
    EXPECT_EQ(part->ranges[0].start, 0u);
    EXPECT_GE(part->ranges[0].count, 2u);
    EXPECT_TRUE(same_pixels(part->film, reference_film(int(part->ranges[0].count))));
}

}  // namespace

// With a noise threshold, the driver stops once every pixel has stopped, each on a checkpoint count, not all on the
// same one; the snapshot reports no active pixel and no time left.
TEST(ProgressiveAdaptive, StopsWhenEveryPixelReachesTheThreshold) {
    ProgressiveRenderer pr(cornell(), kThreads);
    RenderRequest req = request(16, 16);
    req.adaptive.noise_threshold = 0.2f;
    req.adaptive.min_spp = 4;
    const uint64_t g = pr.restart(req);
    Snapshot s;
    for (const auto start = std::chrono::steady_clock::now(); !s.target_reached && before_deadline(start);) {
        pr.wait_for(g, s.spp + 1, 100ms);  // wakes at least every 100 ms: the last pass may publish no new spp
        pr.latest(s);
    }
    ASSERT_TRUE(s.target_reached) << s.spp << " spp, " << s.active_fraction << " active";
    EXPECT_EQ(s.generation, g);
    EXPECT_EQ(s.active_fraction, 0.0);
    EXPECT_EQ(s.seconds_to_threshold, 0.0);
    float lo = 1e30f, hi = 0.f;
    for (float n : s.samples) {
        EXPECT_TRUE(is_adaptive_checkpoint(uint32_t(n))) << n;
        lo = std::min(lo, n);
        hi = std::max(hi, n);
    }
    EXPECT_LT(lo, hi);
}

// ---------------------------------------------------------------- the viewer's denoise toggle
// Turning denoising on after rendering has stopped wakes the driver once: the same accumulation (generation, spp,
// noisy mean bit for bit) comes back with its a-trous image at that spp; nothing is restarted or re-rendered.
TEST(ProgressiveDenoise, StoppedAccumulationIsDenoisedWithoutRestart) {
    ProgressiveRenderer pr(cornell(), kThreads);
    pr.set_target(4, 0.0);
    const uint64_t g = pr.restart(request(24, 16));
    ASSERT_TRUE(pr.wait_for(g, 4, kDeadline));
    Snapshot before;
    ASSERT_TRUE(pr.latest(before));
    EXPECT_TRUE(before.denoised.empty());
    pr.set_denoise(true);
    Snapshot s = before;
    for (const auto start = std::chrono::steady_clock::now(); s.denoised.empty() && before_deadline(start);) {
        std::this_thread::sleep_for(10ms);
        pr.latest(s);
    }
    ASSERT_EQ(s.denoised.size(), s.rgb.size());
    EXPECT_EQ(s.generation, g);
    EXPECT_EQ(s.spp, 4u);
    EXPECT_EQ(s.denoised_spp, 4u);
    EXPECT_EQ(s.rgb, before.rgb);  // the accumulation is untouched
    for (float v : s.denoised) EXPECT_TRUE(std::isfinite(v) && v >= 0.f);
    EXPECT_NE(s.denoised, s.rgb);  // it did filter
}

// Once rendering stops, the denoised image becomes NFOR's: the image `pathview render --denoise` writes for the
// same film (NFOR of a synchronous render's 8 passes with 8-sample features), bit for bit. A restart then shows the
// a-trous filter again until the new accumulation stops.
TEST(ProgressiveDenoise, StoppedAccumulationEndsWithNfor) {
    ProgressiveRenderer pr(cornell(), kThreads);
    pr.set_denoise(true);
    pr.set_target(8, 0.0);
    const RenderRequest req = request(24, 16);
    const uint64_t g = pr.restart(req);
    Snapshot s;
    for (const auto start = std::chrono::steady_clock::now(); !s.denoised_nfor && before_deadline(start);) {
        pr.wait_for(g, s.spp + 1, 10ms);  // a poll: NFOR's image comes without a new spp
        pr.latest(s);
    }
    ASSERT_TRUE(s.denoised_nfor);
    ASSERT_EQ(s.spp, 8u);
    EXPECT_EQ(s.denoised_spp, 8u);
    Renderer r(cornell(), 1);
    r.restart(req.camera, req.settings, req.width, req.height);
    for (int i = 0; i < 8; ++i) r.render_pass();
    const FeatureImage f = render_features(r.traceable(), r.camera(), req.width, req.height, 8, req.settings.seed);
    EXPECT_EQ(s.denoised, denoise_nfor(r.film(), f).rgb);
    EXPECT_EQ(s.rgb, r.film().mean().rgb);

    pr.set_target(0, 0.0);
    RenderSettings other;
    other.seed = 7;
    const uint64_t g2 = pr.restart(request(24, 16, other));
    const Snapshot next = settled(pr, g2, 1);
    ASSERT_EQ(next.generation, g2);
    EXPECT_FALSE(next.denoised_nfor);
}

// While rendering, denoised images follow the accumulation (lagging at most while the filter is throttled) and the
// target's last pass is always denoised.
TEST(ProgressiveDenoise, RenderingPublishesDenoisedImagesAndTheFinalOne) {
    ProgressiveRenderer pr(cornell(), kThreads);
    pr.set_denoise(true);
    pr.set_target(6, 0.0);
    const uint64_t g = pr.restart(request(24, 16));
    Snapshot s;
    for (const auto start = std::chrono::steady_clock::now();
         !(s.target_reached && s.denoised_spp == s.spp) && before_deadline(start);) {
        pr.wait_for(g, s.spp + 1, 10ms);  // a poll: the final denoised image comes without a new spp
        pr.latest(s);
    }
    ASSERT_TRUE(s.target_reached);
    EXPECT_EQ(s.spp, 6u);
    EXPECT_EQ(s.denoised_spp, 6u);
    ASSERT_EQ(s.denoised.size(), s.rgb.size());
    pr.set_denoise(false);
}

}  // namespace pv
