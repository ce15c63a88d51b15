// tests/support/stats.h: the statistics the test suite derives its bounds from: normal quantiles, Sidak-corrected
// thresholds, the regularized incomplete gamma function (chi-square p-values), running moments in double, and the
// two-image comparison of noisy renders (per-pixel Welch with Sidak, plus the total-mean test).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/image/film.h"

namespace pv::test {

// Inverse standard normal CDF (Acklam's rational approximation refined by one Newton step; |error| < 1e-12).
double normal_quantile(double p);
// Two-sided standard normal tail probability 2 (1 - Phi(|z|)).
double normal_two_sided_p(double z);
// Sidak-corrected per-test level for m simultaneous tests at family level alpha.
double sidak_alpha(double alpha, double m);
// k such that a two-sided z-test at the Sidak level passes with probability 1 - alpha over m tests
// (Sidak-corrected two-sided normal quantiles at alpha = 0.01: m = 1 gives 2.576, m = 100 gives 3.889, m = 1e4
// gives 4.891).
double sidak_k(double m, double alpha = 0.01);
// Regularized upper incomplete gamma Q(a, x) = 1 - P(a, x) (series / continued fraction, Numerical Recipes 6.2).
double gamma_q(double a, double x);
// p-value of a chi-square statistic with dof degrees of freedom.
double chi2_p_value(double chi2, double dof);

// Mean and variance in double (Welford).
struct Moments {
    uint64_t n = 0;
    double mean = 0.0, m2 = 0.0;
    void add(double x) {
        ++n;
        const double d = x - mean;
        mean += d / double(n);
        m2 += d * (x - mean);
    }
    double variance() const { return n > 1 ? m2 / double(n - 1) : 0.0; }
    double stderr_of_mean() const;
};

// Per-pixel-channel means and variances of the mean, taken from a Film (double sums).
struct PixelStats {
    int width = 0, height = 0;
    std::vector<double> mean;      // 3 per pixel
    std::vector<double> var_mean;  // sample variance / n, 3 per pixel
    std::vector<uint32_t> n;       // per pixel
    static PixelStats from_film(const Film& film);
    size_t size() const { return mean.size(); }
    // Mean over all pixel-channels and its variance (sum var_p / P^2).
    double total_mean() const;
    double total_mean_variance() const;
};

// Result of comparing two independent noisy images of the same thing (per-pixel Welch tests with Sidak's correction,
// plus the total-mean test).
struct ImageComparison {
    size_t channels = 0;  // pixel-channels tested
    size_t failures = 0;  // with |t| > k
    double k = 0.0;       // Sidak threshold for `channels` tests
    double max_t = 0.0;
    int worst_x = -1, worst_y = -1;
    double total_z = 0.0;  // total-mean z
    bool passed = false;   // failures <= 0.25% and max_t < k + 2 and |total_z| < 3.29
    std::string describe() const;
};
// Welch t per pixel-channel (a channel with zero variance in both images must be equal), Sidak over all.
ImageComparison compare_images(const PixelStats& a, const PixelStats& b, double alpha = 0.01);

}  // namespace pv::test
