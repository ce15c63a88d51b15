// tests/frame/test_threading_adaptive.cpp: adaptive sampling is deterministic for any thread count (the mask depends
// only on the film). Threading* suites also run under TSan.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cstring>

#include "core/frame/renderer.h"
#include "tests/support/scenes.h"

namespace pv {
namespace {

// Same counts and bit-identical sums in every pixel; returns the counts.
std::vector<uint32_t> expect_same_film(const Film& a, const Film& b) {
    std::vector<uint32_t> counts;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const FilmPixel &p = a.pixel(x, y), &q = b.pixel(x, y);
            EXPECT_EQ(p.n, q.n) << x << "," << y;
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(std::memcmp(&p.sum[c], &q.sum[c], sizeof(double)), 0) << x << "," << y;
            counts.push_back(p.n);
        }
    return counts;
}

Film adaptive_film(int threads, uint32_t& passes, double& active) {
    auto scene = test::cornell_box();
    Renderer r(scene, threads);
    AdaptiveSettings a;
    a.noise_threshold = 0.1f;
    a.min_spp = 4;
    r.set_adaptive(a);
    RenderSettings s;
    s.seed = 77;
    r.restart(scene->camera, s, 24, 20);
    for (int i = 0; i < 48 && !r.converged(); ++i) r.render_pass();
    passes = r.stats().spp;
    active = r.adaptive_mask().active_fraction();
    return r.film();
}

TEST(ThreadingAdaptive, OneThreadEqualsTwoThreadsBitForBit) {
    uint32_t pa = 0, pb = 0;
    double fa = 0, fb = 0;
    const Film a = adaptive_film(1, pa, fa), b = adaptive_film(2, pb, fb);
    EXPECT_EQ(pa, pb);
    EXPECT_EQ(fa, fb);
    const std::vector<uint32_t> counts = expect_same_film(a, b);
    // Adaptive sampling did something: the pixels do not all have the same count.
    EXPECT_NE(*std::min_element(counts.begin(), counts.end()), *std::max_element(counts.begin(), counts.end()));
}

// Allocation too: the weights, each pixel's own sample indices and the ray counts behind its cost are the same
// for any thread count.
TEST(ThreadingAdaptive, AllocationOneThreadEqualsTwoThreadsBitForBit) {
    auto scene = test::cornell_box();
    auto film = [&](int threads) {
        Renderer r(scene, threads);
        AdaptiveSettings a;
        a.allocate = true;
        a.min_spp = 4;
        r.set_adaptive(a);
        RenderSettings s;
        s.seed = 78;
        r.restart(scene->camera, s, 24, 20);
        for (int i = 0; i < 40; ++i) r.render_pass();
        return r.film();
    };
    const std::vector<uint32_t> counts = expect_same_film(film(1), film(2));
    EXPECT_NE(*std::min_element(counts.begin(), counts.end()), *std::max_element(counts.begin(), counts.end()));
}

}  // namespace
}  // namespace pv
