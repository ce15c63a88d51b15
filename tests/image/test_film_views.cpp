// tests/image/test_film_views.cpp: Film::views_into (what the viewer's snapshots show) agrees with Film's own mean and
// error estimate, so the published figures are the film's, not a second computation.
// Test kinds: unit
#include <gtest/gtest.h>

#include "core/image/film.h"
#include "core/sampling/rng.h"

namespace pv {

TEST(FilmViews, AgreeWithMeanAndErrorEstimate) {
    Film film(7, 5);
    Pcg32 rng;
    rng.seed(3, 5);
    for (uint32_t s = 0; s < 9; ++s)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 7; ++x) {
                if ((x + y + int(s)) % 4 == 0) continue;  // uneven counts, and pixel (0,0) lacks odd samples early
                film.add(x, y, s, vec3(rng.next_float(), 2.f * rng.next_float(), 0.5f));
            }
    std::vector<float> rgb, rel_error, samples;
    const double est = film.views_into(rgb, rel_error, samples);
    EXPECT_EQ(est, film.estimated_rel_mse());
    const Image mean = film.mean();
    EXPECT_EQ(rgb, mean.rgb);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x) {
            const size_t i = size_t(y) * 7 + size_t(x);
            const FilmPixel& px = film.pixel(x, y);
            EXPECT_EQ(samples[i], float(px.n));
            const std::optional<double> e = pixel_rel_mse(px);
            EXPECT_EQ(rel_error[i], e ? float(std::sqrt(*e)) : 0.f);
        }
    EXPECT_GT(est, 0.0);
}

}  // namespace pv
