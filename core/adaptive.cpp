// core/adaptive.cpp: the noise-threshold mask.
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
    m_active.assign(size_t(width) * size_t(height), 1);
    m_active_count = m_active.size();
    m_worst = 0.0;
}

void AdaptiveMask::update(const Film& film, uint32_t spp, const AdaptiveSettings& s) {
    if (!s.enabled() || spp < s.min_spp || !is_adaptive_checkpoint(spp) || m_active_count == 0) return;
    if (film.width() != m_width || film.height() != m_height) reset(film.width(), film.height());
    const int w = m_width, h = m_height, r = std::max(0, s.radius);
    // Per-pixel relative variance of one sample (relative MSE of the mean x samples), so that a stopped neighbour's
    // estimate stays valid for a pixel that has taken more samples since; a pixel without both halves counts as
    // unconverged (infinite error).
    m_error.resize(size_t(w) * size_t(h));
    m_row.resize(m_error.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const FilmPixel& px = film.pixel(x, y);
            const std::optional<double> e = pixel_rel_mse(px);
            m_error[size_t(y) * size_t(w) + size_t(x)] =
                e ? float(*e * double(px.n)) : std::numeric_limits<float>::infinity();
        }
    // Separable box mean over the window clipped to the image.
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double acc = 0.0;
            const int x0 = std::max(0, x - r), x1 = std::min(w - 1, x + r);
            for (int i = x0; i <= x1; ++i) acc += m_error[size_t(y) * size_t(w) + size_t(i)];
            m_row[size_t(y) * size_t(w) + size_t(x)] = float(acc / double(x1 - x0 + 1));
        }
    const double limit = double(s.noise_threshold) * double(s.noise_threshold);
    m_worst = 0.0;
    for (int y = 0; y < h; ++y) {
        const int y0 = std::max(0, y - r), y1 = std::min(h - 1, y + r);
        for (int x = 0; x < w; ++x) {
            uint8_t& a = m_active[size_t(y) * size_t(w) + size_t(x)];
            if (!a) continue;
            double acc = 0.0;
            for (int j = y0; j <= y1; ++j) acc += m_row[size_t(j) * size_t(w) + size_t(x)];
            // The neighbourhood's relative variance per sample over this pixel's samples.
            const double e = acc / double(y1 - y0 + 1) / double(std::max(1u, film.pixel(x, y).n));
            if (e < limit) {
                a = 0;
                --m_active_count;
            } else {
                m_worst = std::max(m_worst, e);
            }
        }
    }
}

}  // namespace pv
