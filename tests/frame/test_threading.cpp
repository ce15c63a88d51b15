// tests/frame/test_threading.cpp: random numbers depend only on (pixel, sample index, seed), so the Renderer's image is
// bit-identical for any thread count. These suites (Threading*) also run under TSan (make test-tsan), which is why
// they live in a file of their own: the TSan build compiles only test_threading*.cpp and test_progressive*.cpp.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cstring>

#include "core/frame/renderer.h"
#include "tests/support/scenes.h"

namespace pv {
namespace {

// Random numbers depend only on (pixel, index, seed): 1 thread and 2 threads give the same film bit for bit,
// including the sums of squares (the tiles are scheduled differently).
TEST(ThreadingDeterminism, OneThreadEqualsTwoThreadsBitForBit) {
    auto scene = test::cornell_box();
    RenderSettings settings;
    settings.seed = 123;
    const Film a = test::render_with_renderer(scene, scene->camera, settings, 40, 36, 4, 1);
    const Film b = test::render_with_renderer(scene, scene->camera, settings, 40, 36, 4, 2);
    int nonzero = 0;
    for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 40; ++x) {
            const FilmPixel &pa = a.pixel(x, y), &pb = b.pixel(x, y);
            ASSERT_EQ(pa.n, pb.n);
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(std::memcmp(&pa.sum[c], &pb.sum[c], sizeof(double)), 0) << x << "," << y;
                ASSERT_EQ(std::memcmp(&pa.sum_sq[c], &pb.sum_sq[c], sizeof(double)), 0) << x << "," << y;
            }
            nonzero += pa.sum[0] > 0;
        }
    EXPECT_GT(nonzero, 40 * 36 / 2);
}

// A different seed gives a different image (the seed reaches the sampler).
TEST(ThreadingDeterminism, SeedChangesTheImage) {
    auto scene = test::cornell_box();
    RenderSettings s1, s2;
    s1.seed = 1;
    s2.seed = 2;
    const Film a = test::render_with_renderer(scene, scene->camera, s1, 16, 16, 1, 2);
    const Film b = test::render_with_renderer(scene, scene->camera, s2, 16, 16, 1, 2);
    int differ = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) differ += a.pixel(x, y).sum[0] != b.pixel(x, y).sum[0];
    EXPECT_GT(differ, 128);
}

}  // namespace
}  // namespace pv
