// tests/image/test_metrics.cpp: error metrics and log-log fits used by `pathview bench` (relMSE against a reference,
// log-log slopes, efficiency as 1 / (error x time)).
// Test kinds: unit
#include <gtest/gtest.h>

#include "core/base/error.h"
#include "core/image/metrics.h"

namespace pv {
namespace {

Image constant(int w, int h, float v) {
    Image im(w, h);
    for (float& x : im.rgb) x = v;
    return im;
}

TEST(Metrics, ZeroForIdenticalImages) {
    const Image a = constant(4, 3, 0.5f);
    const ErrorMetrics m = compare_images(a, a);
    EXPECT_EQ(m.rel_mse, 0.0);
    EXPECT_EQ(m.rmse, 0.0);
    EXPECT_EQ(m.mape, 0.0);
}

TEST(Metrics, KnownValues) {
    // x = 1.1 everywhere against r = 1: relMSE = 0.01 / 1.01, RMSE = 0.1, MAPE = 0.1 / 1.01.
    const ErrorMetrics m = compare_images(constant(2, 2, 1.1f), constant(2, 2, 1.f));
    EXPECT_NEAR(m.rel_mse, 0.01 / 1.01, 1e-7);
    EXPECT_NEAR(m.rmse, 0.1, 1e-6);
    EXPECT_NEAR(m.mape, 0.1 / 1.01, 1e-6);
    // A black reference pixel: the eps keeps it finite: (0.1)^2 / 0.01 = 1.
    EXPECT_NEAR(compare_images(constant(1, 1, 0.1f), constant(1, 1, 0.f)).rel_mse, 1.0, 1e-6);
}

TEST(Metrics, MeanOverPixelsAndChannels) {
    Image x = constant(2, 1, 0.f), r = constant(2, 1, 0.f);
    x.rgb[0] = 0.1f;  // one value of six differs
    EXPECT_NEAR(compare_images(x, r).rel_mse, 1.0 / 6.0, 1e-6);
}

TEST(Metrics, TrimDropsTheLargestErrors) {
    Image x = constant(10, 10, 1.f), r = constant(10, 10, 1.f);
    x.rgb[0] = 100.f;  // one firefly among 300 values
    EXPECT_GT(compare_images(x, r).rel_mse, 1.0);
    EXPECT_EQ(compare_images(x, r, kMetricEps, 0.01).rel_mse, 0.0);
}

TEST(Metrics, SizeMismatchThrows) { EXPECT_THROW(compare_images(constant(2, 2, 0.f), constant(3, 2, 0.f)), Error); }

TEST(Metrics, ExpectedRelMse) {
    const Image mean = constant(2, 2, 1.f), var = constant(2, 2, 0.0101f);
    EXPECT_NEAR(expected_rel_mse(mean, var), 0.01, 1e-6);
}

TEST(Metrics, Spread) {
    const Spread s = spread_of({1.0, 2.0, 3.0, 4.0});
    EXPECT_DOUBLE_EQ(s.mean, 2.5);
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 4.0);
    EXPECT_NEAR(s.stddev, std::sqrt(5.0 / 3.0), 1e-12);
    EXPECT_EQ(spread_of({2.0}).stddev, 0.0);
}

TEST(Metrics, LogLogSlope) {
    std::vector<double> x, y;
    for (int k = 0; k < 8; ++k) {
        x.push_back(std::ldexp(1.0, k));
        y.push_back(3.0 * std::pow(x.back(), -1.5));
    }
    const SlopeFit f = fit_loglog(x, y);
    EXPECT_NEAR(f.slope, -1.5, 1e-12);
    EXPECT_NEAR(std::exp(f.intercept), 3.0, 1e-9);
    EXPECT_NEAR(f.r2, 1.0, 1e-12);
    EXPECT_EQ(f.points, 8);
    EXPECT_EQ(fit_loglog({1.0}, {1.0}).points, 1);
}

TEST(Metrics, InterpolateLogLog) {
    const std::vector<double> x = {1.0, 4.0}, y = {1.0, 1.0 / 16.0};
    EXPECT_NEAR(*interpolate_loglog(x, y, 2.0), 0.25, 1e-12);
    EXPECT_FALSE(interpolate_loglog(x, y, 8.0).has_value());
    EXPECT_FALSE(interpolate_loglog(x, y, 0.5).has_value());
}

}  // namespace
}  // namespace pv
