// core/distribution.cpp: CDF construction in double and inversion by binary search.
#include "core/distribution.h"

#include <algorithm>

namespace pv {

Distribution1D::Distribution1D(std::vector<float> f) : m_f(std::move(f)) {
    const size_t n = m_f.size();
    m_cdf.assign(n + 1, 0.0);
    for (size_t i = 0; i < n; ++i) {
        const float v = std::isfinite(m_f[i]) ? std::max(m_f[i], 0.f) : 0.f;
        m_f[i] = v;
        m_cdf[i + 1] = m_cdf[i] + double(v) / double(n);
    }
    const double total = m_cdf[n];
    m_integral = static_cast<float>(total);
    if (!(total > 0.0)) {
        std::fill(m_f.begin(), m_f.end(), 1.f);
        for (size_t i = 1; i <= n; ++i) m_cdf[i] = double(i) / double(n);
        m_integral = 0.f;
        return;
    }
    // Normalise f into a density so pdf() is direct.
    for (size_t i = 1; i <= n; ++i) m_cdf[i] /= total;
    for (float& v : m_f) v = static_cast<float>(v / total);
}

float Distribution1D::sample(float u, float* pdf, size_t* cell) const {
    const size_t n = m_f.size();
    // The last i with cdf[i] <= u.
    size_t i = static_cast<size_t>(std::upper_bound(m_cdf.begin(), m_cdf.end(), double(u)) - m_cdf.begin());
    i = std::min(std::max<size_t>(i, 1), n) - 1;
    while (i + 1 < n && m_f[i] == 0.f) ++i;  // never land in an empty cell
    const double width = m_cdf[i + 1] - m_cdf[i];
    double du = width > 0.0 ? (double(u) - m_cdf[i]) / width : 0.5;
    du = std::min(std::max(du, 0.0), 1.0);
    if (pdf) *pdf = m_f[i];
    if (cell) *cell = i;
    const float x = static_cast<float>((double(i) + du) / double(n));
    return std::min(x, kOneMinusEpsilon);
}

float Distribution1D::pdf(float x) const {
    if (m_f.empty() || !(x >= 0.f) || !(x < 1.f)) return 0.f;
    const size_t i = std::min(static_cast<size_t>(x * float(m_f.size())), m_f.size() - 1);
    return m_f[i];
}

Distribution2D::Distribution2D(const std::vector<float>& f, int width, int height) {
    std::vector<float> row_integrals(static_cast<size_t>(height));
    m_rows.reserve(size_t(height));
    for (int y = 0; y < height; ++y) {
        m_rows.emplace_back(std::vector<float>(f.begin() + size_t(y) * width, f.begin() + size_t(y + 1) * width));
        row_integrals[size_t(y)] = m_rows.back().integral();
    }
    m_marginal = Distribution1D(std::move(row_integrals));
}

vec2 Distribution2D::sample(vec2 u, float* pdf) const {
    float pdf_y = 0.f, pdf_x = 0.f;
    size_t row = 0;
    const float y = m_marginal.sample(u.y, &pdf_y, &row);
    const float x = m_rows[row].sample(u.x, &pdf_x, nullptr);
    if (pdf) *pdf = pdf_x * pdf_y;
    return vec2(x, y);
}

float Distribution2D::pdf(vec2 p) const {
    if (m_rows.empty() || !(p.y >= 0.f) || !(p.y < 1.f)) return 0.f;
    const size_t row = std::min(static_cast<size_t>(p.y * float(m_rows.size())), m_rows.size() - 1);
    return m_marginal.pdf(p.y) * m_rows[row].pdf(p.x);
}

}  // namespace pv
