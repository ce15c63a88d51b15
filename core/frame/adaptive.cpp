// core/frame/adaptive.cpp: the noise-threshold mask and the allocation weights.
#include "core/frame/adaptive.h"

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
    m_pilot_next.assign(n, 0);
    m_main_live.assign(n, 0);
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

// m_error = each pixel's relative variance per sample (relative MSE of the mean x samples), so that a stopped
// neighbour's estimate stays valid for a pixel that has taken more samples since; a pixel without both halves
// counts as unconverged (infinite error). Averaged over the window: m_filtered.
void AdaptiveMask::filter_error(const Film& film, int r) {
    const int w = m_width, h = m_height;
    m_error.resize(size_t(w) * size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const FilmPixel& px = film.pixel(x, y);
            const std::optional<double> e = pixel_rel_mse(px);
            m_error[size_t(y) * size_t(w) + size_t(x)] =
                e ? float(*e * double(px.n)) : std::numeric_limits<float>::infinity();
        }
    box_mean(m_error, m_filtered, m_row, w, h, r);
}

void AdaptiveMask::update(const Film& film, uint32_t spp, const AdaptiveSettings& s) {
    if (!s.enabled() || spp < s.min_spp || !is_adaptive_checkpoint(spp) || m_live_count == 0) return;
    if (film.width() != m_width || film.height() != m_height) reset(film.width(), film.height());
    filter_error(film, std::max(0, s.radius));
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

void AdaptiveMask::update_weights(const Film& pilot, const AdaptiveSettings& s) {
    if (!s.allocate || pilot.width() != m_width || pilot.height() != m_height) return;
    // The pilot's first kPilotPasses passes before any weight (a pixel stopped by the threshold has fewer).
    uint32_t most = 0;
    for (const uint32_t k : m_pilot_next) most = std::max(most, k);
    if (most < kPilotPasses) return;
    const int w = m_width, h = m_height, r = std::max(0, s.radius);
    filter_error(pilot, r);
    // Cost: rays per pilot sample plus one for the per-sample work, averaged over the same window.
    for (size_t i = 0; i < m_error.size(); ++i)
        m_error[i] = 1.f + float(double(m_rays[i]) / double(std::max(1u, m_pilot_next[i])));
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

void AdaptiveMask::prepare_pass(bool pilot, uint32_t main_pass) {
    for (size_t i = 0; i < m_active.size(); ++i) {
        if (m_stopped[i]) {
            m_active[i] = 0;
        } else if (pilot) {
            m_active[i] = 1;
        } else {
            ++m_main_live[i];
            m_active[i] = m_weight.empty() || double(m_next[i]) < double(main_pass) * double(m_weight[i]) ? 1 : 0;
        }
    }
}

namespace {

// A film's pixel mean, its two half-buffer means and its variance of the mean, per channel.
struct PixelEstimate {
    double mean[3] = {0, 0, 0}, even[3] = {0, 0, 0}, odd[3] = {0, 0, 0}, var[3] = {0, 0, 0};
    bool halves = false;  // both half buffers hold samples
};

PixelEstimate estimate(const FilmPixel& px) {
    PixelEstimate e;
    e.halves = px.n_even > 0 && px.n_odd() > 0;
    for (int c = 0; c < 3; ++c) {
        e.mean[c] = px.n ? px.mean(c) : 0.0;
        if (e.halves) {
            e.even[c] = px.even_mean(c);
            e.odd[c] = px.odd_mean(c);
        }
        if (px.n > 1) e.var[c] = px.sample_variance(c) / px.n;
    }
    return e;
}

}  // namespace

void AdaptiveMask::combine(const Film& pilot, const Film& main, Film& out) const {
    if (out.width() != m_width || out.height() != m_height) out.reset(m_width, m_height);
    std::vector<FilmPixel>& o = out.mutable_pixels();
    const std::vector<FilmPixel>& ps = pilot.pixels();
    const std::vector<FilmPixel>& ms = main.pixels();
    for (size_t i = 0; i < o.size(); ++i) {
        const FilmPixel& p = ps[i];
        const FilmPixel& m = ms[i];
        FilmPixel& q = o[i];
        // The pilot's weight: its share of the passes the pixel took part in (fixed, whatever the samples are).
        const double passes = double(m_pilot_next[i]) + double(m_main_live[i]);
        if (m.n == 0 || p.n == 0 || passes == 0.0) {  // one film alone (or neither): its own sums
            q = m.n == 0 ? p : m;
            continue;
        }
        const double a = double(m_pilot_next[i]) / passes, b = 1.0 - a;
        const PixelEstimate pe = estimate(p), me = estimate(m);
        q.n = p.n + m.n;
        const bool halves = pe.halves && me.halves;
        // Without both halves of both films there is no honest half-buffer estimate: none (all in the even half).
        q.n_even = halves ? p.n_even + m.n_even : q.n;
        const double n = double(q.n), n_even = double(q.n_even), n_odd = n - n_even;
        for (int c = 0; c < 3; ++c) {
            const double mean = a * pe.mean[c] + b * me.mean[c];
            q.sum[c] = n * mean;
            // The half estimates a x pilot half + b x main half, independent of each other; the even half's sum is
            // set so that the two halves' means differ by exactly their difference and average (by count) to mean.
            const double d = halves ? (a * pe.even[c] + b * me.even[c]) - (a * pe.odd[c] + b * me.odd[c]) : 0.0;
            q.sum_even[c] = halves ? n_even * (mean + d * n_odd / n) : q.sum[c];
            // The variance of the combined mean, a^2 var(pilot mean) + b^2 var(main mean), as Film reads it back.
            const double var = a * a * pe.var[c] + b * b * me.var[c];
            q.sum_sq[c] = n * mean * mean + (n > 1.0 ? var * n * (n - 1.0) : 0.0);
        }
    }
    combine_groups(pilot, main, out);
}

void AdaptiveMask::combine_groups(const Film& pilot, const Film& main, Film& out) const {
    // Light groups: each group combined with the pixel's weights, as its share of the image's sums (means a x pilot
    // + b x main over the combined counts), so the groups still add up to the image.
    const int groups = pilot.groups();
    if (out.groups() != groups) out.set_groups(groups);
    if (groups == 0 || main.groups() != groups) return;
    std::vector<GroupSums>& og = out.mutable_group_sums();
    const std::vector<FilmPixel>& ps = pilot.pixels();
    const std::vector<FilmPixel>& ms = main.pixels();
    const std::vector<FilmPixel>& o = out.pixels();
    for (size_t i = 0; i < o.size(); ++i) {
        const FilmPixel& p = ps[i];
        const FilmPixel& m = ms[i];
        const double passes = double(m_pilot_next[i]) + double(m_main_live[i]);
        for (int g = 0; g < groups; ++g) {
            GroupSums& q = og[i * size_t(groups) + size_t(g)];
            const GroupSums& pg = pilot.group(i, g);
            const GroupSums& mg = main.group(i, g);
            if (m.n == 0 || p.n == 0 || passes == 0.0) {
                q = m.n == 0 ? pg : mg;
                continue;
            }
            const double a = double(m_pilot_next[i]) / passes, b = 1.0 - a;
            const double n = double(o[i].n), n_even = double(o[i].n_even), n_odd = n - n_even;
            const bool halves = p.n_even > 0 && p.n_odd() > 0 && m.n_even > 0 && m.n_odd() > 0;
            for (int c = 0; c < 3; ++c) {
                // combine()'s formulas, each linear in the sums, so the groups add up to the image's.
                const double mean = a * pg.sum[c] / p.n + b * mg.sum[c] / m.n;
                q.sum[c] = n * mean;
                const double d = halves ? (a * pg.sum_even[c] / p.n_even + b * mg.sum_even[c] / m.n_even) -
                                              (a * (pg.sum[c] - pg.sum_even[c]) / p.n_odd() +
                                               b * (mg.sum[c] - mg.sum_even[c]) / m.n_odd())
                                        : 0.0;
                q.sum_even[c] = halves ? n_even * (mean + d * n_odd / n) : q.sum[c];
                // The second moment per sample, weighted as the means are (for the mix's variance estimate only).
                const double sq = a * pg.sum_sq[c] / p.n + b * mg.sum_sq[c] / m.n;
                q.sum_sq[c] = n * sq;
            }
        }
    }
}

}  // namespace pv
