// tests/render/test_raybench.cpp: the ray-rate ceiling's arithmetic and the minimal kernel's bookkeeping (rates
// themselves are timings, measured by `pathview bench --rays`, never asserted here).
// Test kinds: unit
#include <gtest/gtest.h>

#include <cmath>

#include "app/bench/raybench.h"
#include "core/frame/renderer.h"
#include "tests/support/scenes.h"

namespace pv {
namespace {

TEST(RayBench, MixRateIsTheHarmonicMeanWeightedByCounts) {
    RayRates r;
    r.camera = 10.0;
    r.bounce = 5.0;
    r.shadow = 20.0;
    RayMix only_camera;
    only_camera.camera = 7.0;
    EXPECT_DOUBLE_EQ(r.mix_rate(only_camera), 10.0);
    RayMix mix;
    mix.camera = 1.0;
    mix.bounce = 2.0;
    mix.shadow = 1.0;
    // 4 rays in 1/10 + 2/5 + 1/20 seconds.
    EXPECT_DOUBLE_EQ(r.mix_rate(mix), 4.0 / (0.1 + 0.4 + 0.05));
}

TEST(RayBench, MinimalKernelTracesWholePassesOfItsWalk) {
    Renderer r(test::cornell_box(), 2);
    r.restart(r.scene().camera, RenderSettings{}, 16, 16);
    RayBenchOptions o;
    o.width = 16;
    o.height = 16;
    o.threads = 2;
    o.seconds_per_kind = 0.01;
    o.walk_depth = 3;
    const MinimalKernelRate mk = measure_minimal_kernel(r.traceable(), r.camera(), o);
    ASSERT_GT(mk.mix.camera, 0.0);
    const double passes = mk.mix.camera / (16.0 * 16.0);
    EXPECT_EQ(passes, std::floor(passes));  // one camera ray per pixel per pass
    // At most walk_depth bounces per camera ray, and at most one shadow ray per vertex (a hit by a camera or bounce
    // ray); in the Cornell box most rays hit, so most vertices get one.
    EXPECT_LE(mk.mix.bounce, 3.0 * mk.mix.camera);
    EXPECT_GT(mk.mix.bounce, 1.0 * mk.mix.camera);
    EXPECT_LE(mk.mix.shadow, mk.mix.camera + mk.mix.bounce);
    EXPECT_GT(mk.mix.shadow, 0.5 * (mk.mix.camera + mk.mix.bounce));
    EXPECT_GT(mk.rays_per_second, 0.0);
    EXPECT_TRUE(std::isfinite(mk.estimate));
    EXPECT_GT(mk.estimate, 0.0);
}

}  // namespace
}  // namespace pv
