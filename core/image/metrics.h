// core/image/metrics.h: image error metrics against a reference and small statistics for speed-vs-error reports.
// Conventions (as tev and SimpleImageIO compute them): every metric is a mean over pixels AND channels;
// relMSE = (x - r)^2 / (r^2 + eps), MAPE = |x - r| / (|r| + eps), eps = 0.01, no trimming unless asked.
// Sums are in double. Mismatched image sizes throw pv::Error.
#pragma once

#include <optional>
#include <vector>

#include "core/image/film.h"

namespace pv {

constexpr double kMetricEps = 0.01;

struct ErrorMetrics {
    double rel_mse = 0.0;
    double rmse = 0.0;
    double mape = 0.0;
};

// Error of `image` against `reference`. `trim` drops that fraction of the largest per-value relative squared
// errors from relMSE only (e.g. 0.001 for SimpleImageIO's outlier-rejected variant); 0 keeps everything.
ErrorMetrics compare_images(const Image& image, const Image& reference, double eps = kMetricEps, double trim = 0.0);
// The same over n values of two buffers (an image's channels without copying them into an Image).
ErrorMetrics compare_values(const float* image, const float* reference, size_t n, double eps = kMetricEps,
                            double trim = 0.0);

// The relMSE that the noise of a Monte Carlo image is expected to have: mean of var_of_mean / (mean^2 + eps),
// from a film's per-pixel variance of the mean. Valid for independent samples only.
double expected_rel_mse(const Image& mean, const Image& var_of_mean, double eps = kMetricEps);

// A picture that reads as dark: the mean of its pixels' Rec. 709 luminance, each clamped to [0, 1] as the display
// shows it at exposure 0 (a visible lamp counts as white, not as its radiance), below kDarkMeanLuminance. Measured
// at 4 spp (160x120) on scenes lit by their own emitters only: Blender's glTF still life lit by its one lamp (its
// world not exported) 0.0068, the conference room inside with no light reaching it 0; lit as meant, the built-in
// Cornell box 0.052, the glTF showcase 0.076, the many-lights scene 0.13. The bound sits near the geometric mean
// of the darkest well-lit scene and the dark still life (a factor of 2.6 to 2.9 from each). Used for the hint that
// the scene's own lights leave the view dark (pathview render, the viewer's Light section).
constexpr double kDarkMeanLuminance = 0.02;
// That mean over n RGB pixels (3 floats each); non-finite values count as 0.
double mean_display_luminance(const float* rgb, size_t pixels);

// Mean, sample standard deviation, min and max of a set of values (zeros when empty; stddev 0 for one value).
struct Spread {
    double mean = 0.0, stddev = 0.0, min = 0.0, max = 0.0;
};
Spread spread_of(const std::vector<double>& values);

// Least-squares line through (log x, log y): the slope of a log-log plot. Points with x or y <= 0 are skipped;
// fewer than two points give slope 0 and r2 0.
struct SlopeFit {
    double slope = 0.0, intercept = 0.0, r2 = 0.0;
    int points = 0;
};
SlopeFit fit_loglog(const std::vector<double>& x, const std::vector<double>& y);

// y at x by linear interpolation in log-log space over points sorted by increasing x; nothing outside [x0, xn].
std::optional<double> interpolate_loglog(const std::vector<double>& x, const std::vector<double>& y, double at);

}  // namespace pv
