// tests/support/stats.cpp: see stats.h.
#include "tests/support/stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace pv::test {

double normal_quantile(double p) {
    if (!(p > 0.0 && p < 1.0))
        return p <= 0.0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    // Acklam 2003.
    static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                               1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                               6.680131188771972e+01, -1.328068155288572e+01};
    static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                               -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
    static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                               3.754408661907416e+00};
    const double plow = 0.02425;
    double x;
    if (p < plow) {
        const double q = std::sqrt(-2 * std::log(p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    } else if (p <= 1 - plow) {
        const double q = p - 0.5, r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
    } else {
        const double q = std::sqrt(-2 * std::log1p(-p));
        x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    }
    // One Halley step on Phi(x) - p.
    const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
    const double u = e * std::sqrt(2 * M_PI) * std::exp(x * x / 2);
    return x - u / (1 + x * u / 2);
}

double normal_two_sided_p(double z) { return std::erfc(std::fabs(z) / std::sqrt(2.0)); }

double sidak_alpha(double alpha, double m) { return -std::expm1(std::log1p(-alpha) / m); }

double sidak_k(double m, double alpha) {
    const double a = sidak_alpha(alpha, m);
    return -normal_quantile(0.5 * a);
}

namespace {
double gamma_p_series(double a, double x) {
    double sum = 1.0 / a, del = sum, ap = a;
    for (int n = 0; n < 100000; ++n) {
        ap += 1.0;
        del *= x / ap;
        sum += del;
        if (std::fabs(del) < std::fabs(sum) * 1e-16) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}
double gamma_q_fraction(double a, double x) {
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double del = d * c;
        h *= del;
        if (std::fabs(del - 1.0) < 1e-16) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}
}  // namespace

double gamma_q(double a, double x) {
    if (!(x >= 0.0) || !(a > 0.0)) return std::numeric_limits<double>::quiet_NaN();
    if (x == 0.0) return 1.0;
    if (x < a + 1.0) return 1.0 - gamma_p_series(a, x);
    return gamma_q_fraction(a, x);
}

double chi2_p_value(double chi2, double dof) { return gamma_q(0.5 * dof, 0.5 * chi2); }

double Moments::stderr_of_mean() const { return n > 0 ? std::sqrt(variance() / double(n)) : 0.0; }

PixelStats PixelStats::from_film(const Film& film) {
    PixelStats s;
    s.width = film.width();
    s.height = film.height();
    const size_t np = size_t(s.width) * size_t(s.height);
    s.mean.resize(np * 3);
    s.var_mean.resize(np * 3);
    s.n.resize(np);
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const FilmPixel& px = film.pixel(x, y);
            const size_t i = size_t(y) * size_t(s.width) + size_t(x);
            s.n[i] = px.n;
            for (int c = 0; c < 3; ++c) {
                const double m = px.n ? px.sum[c] / px.n : 0.0;
                double v = 0.0;
                if (px.n > 1) v = std::max(0.0, (px.sum_sq[c] - px.n * m * m) / (px.n - 1)) / px.n;
                s.mean[i * 3 + c] = m;
                s.var_mean[i * 3 + c] = v;
            }
        }
    return s;
}

double PixelStats::total_mean() const {
    double acc = 0.0;
    for (double m : mean) acc += m;
    return mean.empty() ? 0.0 : acc / double(mean.size());
}

double PixelStats::total_mean_variance() const {
    double acc = 0.0;
    for (double v : var_mean) acc += v;
    const double p = double(var_mean.size());
    return p > 0 ? acc / (p * p) : 0.0;
}

std::string ImageComparison::describe() const {
    std::ostringstream s;
    s << failures << " of " << channels << " pixel-channels with |t| > k = " << k << ", max |t| = " << max_t << " at ("
      << worst_x << ", " << worst_y << "), total-mean z = " << total_z;
    return s.str();
}

ImageComparison compare_images(const PixelStats& a, const PixelStats& b, double alpha) {
    ImageComparison r;
    r.channels = a.size();
    r.k = sidak_k(double(r.channels), alpha);
    for (size_t i = 0; i < a.size(); ++i) {
        const double diff = a.mean[i] - b.mean[i];
        const double se = std::sqrt(a.var_mean[i] + b.var_mean[i]);
        double t;
        if (se > 0.0) {
            t = diff / se;
        } else {
            // Both constant: must agree to float round-off.
            t = std::fabs(diff) <= 1e-6 * std::max(std::fabs(a.mean[i]), 1.0) ? 0.0
                                                                              : std::numeric_limits<double>::infinity();
        }
        if (std::fabs(t) > r.k) r.failures++;
        if (std::fabs(t) > r.max_t) {
            r.max_t = std::fabs(t);
            r.worst_x = int((i / 3) % size_t(a.width));
            r.worst_y = int((i / 3) / size_t(a.width));
        }
    }
    const double va = a.total_mean_variance(), vb = b.total_mean_variance();
    r.total_z = (va + vb) > 0 ? (a.total_mean() - b.total_mean()) / std::sqrt(va + vb) : 0.0;
    r.passed = double(r.failures) <= 0.0025 * double(r.channels) && r.max_t < r.k + 2.0 && std::fabs(r.total_z) < 3.29;
    return r;
}

}  // namespace pv::test
