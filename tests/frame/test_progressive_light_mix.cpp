// tests/frame/test_progressive_light_mix.cpp: the viewer's live mix of light groups (ProgressiveRenderer::
// set_light_gains, docs/light-groups.md): a new mix is published without a restart or a pass (same generation and
// sample count), its image is the synchronous Renderer's mixed film, bit for bit, and the mix with every gain 1 is the
// image published before, bit for bit.
// Test kinds: unit
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "core/frame/progressive.h"
#include "support/scenes.h"

namespace pv {
namespace {

using namespace std::chrono_literals;

#ifdef PATHVIEW_SANITIZED
constexpr int kThreads = 1;
#else
constexpr int kThreads = 2;
#endif

// Waits (polling) for a snapshot newer than `after`; generation 0 at the deadline.
Snapshot next_snapshot(const ProgressiveRenderer& pr, const Snapshot& after) {
    Snapshot s = after;
    for (const auto start = std::chrono::steady_clock::now(); std::chrono::steady_clock::now() - start < 300s;) {
        if (pr.latest(s)) return s;
        std::this_thread::sleep_for(5ms);
    }
    return Snapshot{};
}

TEST(ProgressiveLightMix, GainsRemixWithoutRestart) {
    auto scene = test::open_box(true);
    scene->environment.sun_irradiance = vec3(3.f);
    scene->environment.sun_direction = glm::normalize(vec3(0.3f, 1.f, 0.4f));
    RenderRequest req;
    req.camera = scene->camera;
    req.settings.seed = 5;
    req.width = 20;
    req.height = 14;
    constexpr uint32_t kSpp = 3;
    ProgressiveRenderer pr(scene, kThreads);
    pr.set_target(kSpp, 0.0);
    const uint64_t g = pr.restart(req);
    ASSERT_TRUE(pr.wait_for(g, kSpp, 300s));
    Snapshot first;
    ASSERT_TRUE(pr.latest(first));
    ASSERT_EQ(first.light_groups, (std::vector<std::string>{"default", "sky", "sun"}));

    const LightGains gains{vec3(2.f), vec3(0.5f, 1.f, 1.5f), vec3(0.f)};
    pr.set_light_gains(gains);
    const Snapshot mixed = next_snapshot(pr, first);
    EXPECT_EQ(mixed.generation, g);
    EXPECT_EQ(mixed.spp, kSpp);

    Renderer r(scene, 1);
    r.set_light_groups(true);
    r.restart(req.camera, req.settings, req.width, req.height);
    for (uint32_t i = 0; i < kSpp; ++i) r.render_pass();
    EXPECT_EQ(mixed.rgb, r.film().mixed(gains).mean().rgb);
    EXPECT_NE(mixed.rgb, first.rgb);

    pr.set_light_gains(LightGains(3, vec3(1.f)));
    const Snapshot back = next_snapshot(pr, mixed);
    EXPECT_EQ(back.generation, g);
    EXPECT_EQ(back.rgb, first.rgb);
}

}  // namespace
}  // namespace pv
