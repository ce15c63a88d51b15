// tests/frame/test_threading_paths_in_flight.cpp: the Renderer's paths interleaved per thread (PathWalker, render_pass)
// leave the image as it was. A test_threading* file, so the TSan build compiles and runs it.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cstring>

#include "core/frame/renderer.h"
#include "support/scenes.h"

namespace pv {
namespace {

// The Renderer's passes (2 threads) with 1, 3 and 8 paths in flight per thread: the same film sums, counts and ray
// totals, bit for bit, with adaptive sampling by allocation (each pixel its own sample indices and its ray counts) and
// without.
TEST(ThreadingPathsInFlight, ImageDoesNotDependOnPathsInFlight) {
    const auto scene = test::open_box(false);
    for (const bool allocate : {false, true}) {
        SCOPED_TRACE(allocate ? "adaptive allocation" : "uniform");
        std::vector<Film> films;
        std::vector<uint64_t> rays;
        for (const int in_flight : {1, 3, 8}) {
            Renderer r(scene, 2);
            r.set_paths_in_flight(in_flight);
            ASSERT_EQ(r.paths_in_flight(), in_flight);
            AdaptiveSettings adaptive;
            adaptive.allocate = allocate;
            adaptive.min_spp = 4;
            r.set_adaptive(adaptive);
            RenderSettings settings;
            settings.sky_guide = SkyGuideMode::Off;
            r.restart(scene->camera, settings, 20, 14);
            for (int pass = 0; pass < 12; ++pass) r.render_pass();
            films.push_back(r.film());
            rays.push_back(r.stats().rays + r.stats().shadow_rays);
        }
        for (size_t k = 1; k < films.size(); ++k) {
            EXPECT_EQ(rays[k], rays[0]);
            for (int y = 0; y < 14; ++y)
                for (int x = 0; x < 20; ++x) {
                    const FilmPixel& a = films[0].pixel(x, y);
                    const FilmPixel& b = films[k].pixel(x, y);
                    ASSERT_EQ(a.n, b.n) << x << "," << y;
                    ASSERT_EQ(std::memcmp(a.sum, b.sum, sizeof a.sum), 0) << x << "," << y;
                    ASSERT_EQ(std::memcmp(a.sum_sq, b.sum_sq, sizeof a.sum_sq), 0) << x << "," << y;
                    ASSERT_EQ(std::memcmp(a.sum_even, b.sum_even, sizeof a.sum_even), 0) << x << "," << y;
                }
        }
    }
}

}  // namespace
}  // namespace pv
