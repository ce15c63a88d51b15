// core/image/metrics.cpp: error metrics and log-log fits (see metrics.h).
#include "core/image/metrics.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/base/error.h"

namespace pv {

ErrorMetrics compare_images(const Image& image, const Image& reference, double eps, double trim) {
    if (image.width != reference.width || image.height != reference.height)
        throw Error("compare_images: image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                    " but the reference is " + std::to_string(reference.width) + "x" +
                    std::to_string(reference.height));
    return compare_values(image.rgb.data(), reference.rgb.data(), image.rgb.size(), eps, trim);
}

ErrorMetrics compare_values(const float* image, const float* reference, size_t n, double eps, double trim) {
    ErrorMetrics m;
    if (n == 0) return m;
    double se = 0.0, rse = 0.0, ape = 0.0;
    std::vector<double> rel;
    if (trim > 0.0) rel.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        const double x = image[i], r = reference[i], d = x - r;
        const double q = d * d / (r * r + eps);
        se += d * d;
        rse += q;
        ape += std::fabs(d) / (std::fabs(r) + eps);
        if (trim > 0.0) rel.push_back(q);
    }
    m.rmse = std::sqrt(se / double(n));
    m.mape = ape / double(n);
    if (trim > 0.0) {
        const size_t keep = n - std::min(n - 1, static_cast<size_t>(std::floor(trim * double(n))));
        std::nth_element(rel.begin(), rel.begin() + ptrdiff_t(keep - 1), rel.end());
        double s = 0.0;
        for (size_t i = 0; i < keep; ++i) s += rel[i];
        m.rel_mse = s / double(keep);
    } else {
        m.rel_mse = rse / double(n);
    }
    return m;
}

double expected_rel_mse(const Image& mean, const Image& var_of_mean, double eps) {
    if (mean.rgb.size() != var_of_mean.rgb.size() || mean.rgb.empty()) return 0.0;
    double acc = 0.0;
    for (size_t i = 0; i < mean.rgb.size(); ++i) {
        const double r = mean.rgb[i];
        acc += double(var_of_mean.rgb[i]) / (r * r + eps);
    }
    return acc / double(mean.rgb.size());
}

Spread spread_of(const std::vector<double>& v) {
    Spread s;
    if (v.empty()) return s;
    double sum = 0.0;
    s.min = s.max = v[0];
    for (double x : v) {
        sum += x;
        s.min = std::min(s.min, x);
        s.max = std::max(s.max, x);
    }
    s.mean = sum / double(v.size());
    if (v.size() > 1) {
        double ss = 0.0;
        for (double x : v) ss += (x - s.mean) * (x - s.mean);
        s.stddev = std::sqrt(ss / double(v.size() - 1));
    }
    return s;
}

SlopeFit fit_loglog(const std::vector<double>& x, const std::vector<double>& y) {
    SlopeFit f;
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    int n = 0;
    for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
        if (!(x[i] > 0.0) || !(y[i] > 0.0)) continue;
        const double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
        syy += ly * ly;
        ++n;
    }
    f.points = n;
    if (n < 2) return f;
    const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n, cxy = sxy - sx * sy / n;
    if (!(vx > 0.0)) return f;
    f.slope = cxy / vx;
    f.intercept = (sy - f.slope * sx) / n;
    f.r2 = vy > 0.0 ? cxy * cxy / (vx * vy) : 1.0;
    return f;
}

std::optional<double> interpolate_loglog(const std::vector<double>& x, const std::vector<double>& y, double at) {
    const size_t n = std::min(x.size(), y.size());
    if (n == 0 || !(at > 0.0)) return std::nullopt;
    for (size_t i = 0; i + 1 < n; ++i) {
        if (at >= x[i] && at <= x[i + 1] && x[i] > 0.0 && y[i] > 0.0 && y[i + 1] > 0.0) {
            if (x[i + 1] == x[i]) return y[i];
            const double t = (std::log(at) - std::log(x[i])) / (std::log(x[i + 1]) - std::log(x[i]));
            return std::exp(std::log(y[i]) + t * (std::log(y[i + 1]) - std::log(y[i])));
        }
    }
    if (n == 1 && at == x[0]) return y[0];
    return std::nullopt;
}

double mean_display_luminance(const float* rgb, size_t pixels) {
    double sum = 0.0;
    for (size_t i = 0; i < pixels; ++i) {
        const double y = 0.2126 * rgb[3 * i] + 0.7152 * rgb[3 * i + 1] + 0.0722 * rgb[3 * i + 2];
        if (std::isfinite(y)) sum += std::clamp(y, 0.0, 1.0);
    }
    return pixels ? sum / double(pixels) : 0.0;
}

}  // namespace pv
