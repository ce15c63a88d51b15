// tests/test_progressive_adaptive.cpp: the driver stops at the request's noise threshold and reports the fraction
// of active pixels (0 once stopped) and no time left. "Progressive" suites also run under TSan.
#include "core/progressive.h"
#include "core/scene_file.h"

#include <gtest/gtest.h>

namespace pv {
namespace {

using namespace std::chrono_literals;

#ifdef PATHVIEW_SANITIZED
constexpr int kThreads = 1;
#else
constexpr int kThreads = 2;
#endif

TEST(ProgressiveAdaptive, StopsWhenEveryPixelReachesTheThreshold) {
    const auto scene = std::make_shared<const Scene>(load_scene(builtin_scene_path()));
    ProgressiveRenderer pr(scene, kThreads);
    RenderRequest req;
    req.camera = scene->camera;
    req.width = 16;
    req.height = 16;
    req.adaptive.noise_threshold = 0.2f;
    req.adaptive.min_spp = 4;
    const uint64_t g = pr.restart(req);
    Snapshot s;
    bool stopped = false;
    for (int i = 0; i < 2000 && !stopped; ++i) {
        pr.wait_for(g, s.spp + 1, 100ms);
        if (pr.latest(s) && s.generation == g) {
            stopped = s.target_reached;
        }
    }
    ASSERT_TRUE(stopped) << s.spp << " spp, " << s.active_fraction << " active";
    EXPECT_EQ(s.active_fraction, 0.0);
    EXPECT_EQ(s.seconds_to_threshold, 0.0);
    // Every pixel stopped on a checkpoint count, and not all on the same one.
    float lo = 1e30f, hi = 0.f;
    for (float n : s.samples) {
        EXPECT_TRUE(is_adaptive_checkpoint(uint32_t(n))) << n;
        lo = std::min(lo, n);
        hi = std::max(hi, n);
    }
    EXPECT_LT(lo, hi);
}

}  // namespace
}  // namespace pv
