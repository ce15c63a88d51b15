// tests/image/test_film_accumulation.cpp: a hundred million samples in one film pixel keep an exact count and mean;
// non-finite and negative samples are refused.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/image/film.h"

namespace pv {
namespace {

// ---------------------------------------------------------------- long accumulation

TEST(FilmAccumulation, HundredMillionSamplesStayExact) {
    Film film(1, 1);
    const vec3 v(0.1f, 3.3f, 1e-3f);
    const uint32_t n = 100000000u;
    for (uint32_t i = 0; i < n; ++i) film.add(0, 0, i, v);
    const FilmPixel& px = film.pixel(0, 0);
    ASSERT_EQ(px.n, n);
    const Image mean = film.mean();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean.rgb[size_t(c)], v[c], 1e-6 * v[c]) << "channel " << c;
    // Non-finite and negative samples are refused.
    EXPECT_FALSE(film.add(0, 0, n, vec3(std::nanf(""), 0.f, 0.f)));
    EXPECT_FALSE(film.add(0, 0, n, vec3(std::numeric_limits<float>::infinity())));
    EXPECT_FALSE(film.add(0, 0, n, vec3(-1.f, 0.f, 0.f)));
    EXPECT_EQ(film.pixel(0, 0).n, n);
}

}  // namespace
}  // namespace pv
