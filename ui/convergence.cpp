// ui/convergence.cpp: resampling and the slope fit.
#include "convergence.h"

#include <algorithm>
#include <cmath>

namespace pv::ui {

void ConvergenceHistory::add(double spp, double seconds, double rel_mse) {
    if (!(rel_mse > 0.0) || !(spp > 0.0) || !(seconds > 0.0)) return;
    const Point p{std::log10(spp), std::log10(seconds), std::log10(rel_mse)};
    // Keep x increasing: a resample needs sorted abscissae in both time and spp.
    if (!m_points.empty() && (p.log_spp <= m_points.back().log_spp || p.log_seconds <= m_points.back().log_seconds))
        return;
    m_points.push_back(p);
}

std::vector<float> ConvergenceHistory::resample(bool by_seconds, int n, float& lo, float& hi) const {
    std::vector<float> out;
    if (m_points.size() < 2 || n < 2) return out;
    auto x_of = [&](const Point& p) { return by_seconds ? p.log_seconds : p.log_spp; };
    lo = float(x_of(m_points.front()));
    hi = float(x_of(m_points.back()));
    out.resize(size_t(n));
    size_t j = 0;
    for (int i = 0; i < n; ++i) {
        // Linear interpolation in log-log space between the two recorded points around x.
        const double x = lo + (hi - lo) * double(i) / double(n - 1);
        while (j + 2 < m_points.size() && x_of(m_points[j + 1]) < x) ++j;
        const Point& a = m_points[j];
        const Point& b = m_points[j + 1];
        const double t = std::clamp((x - x_of(a)) / (x_of(b) - x_of(a)), 0.0, 1.0);
        out[size_t(i)] = float(a.log_mse + t * (b.log_mse - a.log_mse));
    }
    return out;
}

std::vector<float> ConvergenceHistory::log_log_by_seconds(int n, float& lo, float& hi) const {
    return resample(true, n, lo, hi);
}

std::vector<float> ConvergenceHistory::log_log_by_spp(int n, float& lo, float& hi) const {
    return resample(false, n, lo, hi);
}

double ConvergenceHistory::slope_vs_spp() const {
    // Fit the upper half of the log(spp) range only: the first few estimates (2, 3, 4 spp) are themselves very
    // noisy and would hide the asymptotic rate.
    if (m_points.size() < 2) return 0.0;
    const double from = 0.5 * (m_points.front().log_spp + m_points.back().log_spp);
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const Point& p : m_points) {
        if (p.log_spp < from) continue;
        n += 1.0;
        sx += p.log_spp;
        sy += p.log_mse;
        sxx += p.log_spp * p.log_spp;
        sxy += p.log_spp * p.log_mse;
    }
    const double den = n * sxx - sx * sx;
    return n >= 2.0 && den > 0.0 ? (n * sxy - sx * sy) / den : 0.0;
}

}  // namespace pv::ui
