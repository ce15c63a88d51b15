// core/adaptive.cpp: the noise-threshold mask and the allocation weights.
#include "core/adaptive.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pv {

bool is_adaptive_checkpoint(uint32_t n) {
    if (n == 0) return false;
    const uint32_t odd = n >> __builtin_ctz(n);  // n = odd * 2^j
    return odd == 1 || odd == 3;
}

void AdaptiveMask::reset(int width, int height) {
    m_width = width;
    m_height = height;
    const size_t n = size_t(width) * size_t(height);
    m_active.assign(n, 1);
    m_stopped.assign(n, 0);
    m_live_count = n;
    m_worst = 0.0;
    m_weight.clear();
    m_next.assign(n, 0);
    m_rays.assign(n, 0);
}

namespace {

// out = the mean of `in` over the (2r+1)^2 window clipped to the w x h image (separable; `row` is scratch).
void box_mean(const std::vector<float>& in, std::vector<float>& out, std::vector<float>& row, int w, int h, int r) {
    row.resize(in.size());
    out.resize(in.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double acc = 0.0;
            const int x0 = std::max(0, x - r), x1 = std::min(w - 1, x + r);
            for (int i = x0; i <= x1; ++i) acc += in[size_t(y) * size_t(w) + size_t(i)];
            row[size_t(y) * size_t(w) + size_t(x)] = float(acc / double(x1 - x0 + 1));
        }
    for (int y = 0; y < h; ++y) {
        const int y0 = std::max(0, y - r), y1 = std::min(h - 1, y + r);
        for (int x = 0; x < w; ++x) {
            double acc = 0.0;
            for (int j = y0; j <= y1; ++j) acc += row[size_t(j) * size_t(w) + size_t(x)];
            out[size_t(y) * size_t(w) + size_t(x)] = float(acc / double(y1 - y0 + 1));
        }
    }
}

}  // namespace

void AdaptiveMask::update(const Film& film, uint32_t spp, const AdaptiveSettings& s) {
    if (!s.masks() || spp < s.min_spp || !is_adaptive_checkpoint(spp) || m_live_count == 0) return;
    if (film.width() != m_width || film.height() != m_height) reset(film.width(), film.height());
    const int w = m_width, h = m_height, r = std::max(0, s.radius);
    // Per-pixel relative variance of one sample (relative MSE of the mean x samples), so that a stopped neighbour's
    // estimate stays valid for a pixel that has taken more samples since; a pixel without both halves counts as
    // unconverged (infinite error). Averaged over the window: m_filtered.
    m_error.resize(size_t(w) * size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const FilmPixel& px = film.pixel(x, y);
            const std::optional<double> e = pixel_rel_mse(px);
            m_error[size_t(y) * size_t(w) + size_t(x)] =
                e ? float(*e * double(px.n)) : std::numeric_limits<float>::infinity();
        }
    box_mean(m_error, m_filtered, m_row, w, h, r);
    if (s.enabled()) {
        const double limit = double(s.noise_threshold) * double(s.noise_threshold);
        m_worst = 0.0;
        for (size_t i = 0; i < m_filtered.size(); ++i) {
            if (m_stopped[i]) continue;
            // The neighbourhood's relative variance per sample over this pixel's samples.
            const double e = double(m_filtered[i]) / double(std::max(1u, film.pixels()[i].n));
            if (e < limit) {
                m_stopped[i] = 1;
                m_active[i] = 0;
                --m_live_count;
            } else {
                m_worst = std::max(m_worst, e);
            }
        }
    }
    if (!s.allocate) return;
    // Cost: rays per sample plus one for the per-sample work, averaged over the same window.
    for (size_t i = 0; i < m_error.size(); ++i)
        m_error[i] = 1.f + float(double(m_rays[i]) / double(std::max(1u, m_next[i])));
    box_mean(m_error, m_cost, m_row, w, h, r);
    // Scores sqrt(v / c) (v: the filtered relative variance per sample), weights score / the quantile's score.
    m_sorted.clear();
    for (size_t i = 0; i < m_filtered.size(); ++i) {
        const float v = m_filtered[i];
        m_error[i] = std::isfinite(v) ? std::sqrt(std::max(0.f, v) / m_cost[i]) : v;
        if (std::isfinite(m_error[i])) m_sorted.push_back(m_error[i]);
    }
    float ref = 0.f;
    if (!m_sorted.empty()) {
        const size_t k = std::min(m_sorted.size() - 1, size_t(kAllocationQuantile * double(m_sorted.size() - 1)));
        std::nth_element(m_sorted.begin(), m_sorted.begin() + std::ptrdiff_t(k), m_sorted.end());
        ref = m_sorted[k];
    }
    m_weight.resize(m_error.size());
    for (size_t i = 0; i < m_error.size(); ++i) {
        const float e = m_error[i];
        m_weight[i] =
            ref > 0.f && std::isfinite(ref) && std::isfinite(e) ? std::clamp(e / ref, kAllocationFloor, 1.f) : 1.f;
    }
}

void AdaptiveMask::prepare_pass(uint32_t pass, const AdaptiveSettings& s) {
    if (!s.allocate || m_weight.empty()) return;
    for (size_t i = 0; i < m_active.size(); ++i)
        m_active[i] = !m_stopped[i] && double(m_next[i]) < double(pass) * double(m_weight[i]) ? 1 : 0;
}

}  // namespace pv
