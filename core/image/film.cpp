// core/image/film.cpp: means, variances and the half-buffer error estimate.
#include "core/image/film.h"

#include <cassert>

namespace pv {

void Film::reset(int width, int height) {
    m_width = width;
    m_height = height;
    m_pixels.assign(size_t(width) * size_t(height), FilmPixel{});
    m_group_sums.assign(m_groups > 0 ? m_pixels.size() * size_t(m_groups) : 0, GroupSums{});
}

void Film::set_groups(int count) {
    m_groups = count > 1 ? count : 0;
    m_group_sums.assign(m_groups > 0 ? m_pixels.size() * size_t(m_groups) : 0, GroupSums{});
}

void Film::add_groups(size_t i, bool even, const vec3* group_L) {
    GroupSums* g = &m_group_sums[i * size_t(m_groups)];
    for (int k = 0; k < m_groups; ++k) {
        const vec3 l = group_L[k];
        if (l == vec3(0.f)) continue;  // most samples reach few groups
        for (int c = 0; c < 3; ++c) {
            const double v = l[c];
            g[k].sum[c] += v;
            g[k].sum_sq[c] += v * v;
            if (even) g[k].sum_even[c] += v;
        }
    }
}

Image Film::group_mean(int g) const {
    Image out(m_width, m_height);
    if (g < 0 || g >= m_groups) return out;
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const double inv = m_pixels[i].n ? 1.0 / m_pixels[i].n : 0.0;
        const GroupSums& s = group(i, g);
        for (int c = 0; c < 3; ++c) out.rgb[i * 3 + c] = static_cast<float>(s.sum[c] * inv);
    }
    return out;
}

void Film::mixed_into(const LightGains& gains, Film& out) const {
    out.m_width = m_width;
    out.m_height = m_height;
    out.m_groups = 0;
    out.m_group_sums.clear();
    out.m_pixels = m_pixels;
    const int n = std::min(m_groups, int(gains.size()));
    if (n == 0 || gains_identity(gains)) return;
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const FilmPixel& p = m_pixels[i];
        FilmPixel& q = out.m_pixels[i];
        for (int c = 0; c < 3; ++c) {
            double sum = p.sum[c], even = p.sum_even[c], own_sq = 0.0, own_sq_mixed = 0.0;
            for (int g = 0; g < m_groups; ++g) {
                const GroupSums& s = group(i, g);
                const double k = g < n ? double(gains[size_t(g)][c]) : 1.0;
                sum += (k - 1.0) * s.sum[c];
                even += (k - 1.0) * s.sum_even[c];
                own_sq += s.sum_sq[c];
                own_sq_mixed += k * k * s.sum_sq[c];
            }
            const double ratio = p.sum[c] > 0.0 ? sum / p.sum[c] : 1.0;
            q.sum[c] = std::max(0.0, sum);
            q.sum_even[c] = std::max(0.0, even);
            q.sum_sq[c] = own_sq_mixed + std::max(0.0, p.sum_sq[c] - own_sq) * ratio * ratio;
        }
    }
}

Film Film::from_pixels(int width, int height, std::vector<FilmPixel> pixels) {
    assert(pixels.size() == size_t(width) * size_t(height));
    Film f;
    f.m_width = width;
    f.m_height = height;
    f.m_pixels = std::move(pixels);
    return f;
}

Film Film::from_pixels(int width, int height, std::vector<FilmPixel> pixels, int groups,
                       std::vector<GroupSums> group_sums) {
    Film f = from_pixels(width, height, std::move(pixels));
    assert(groups > 1 && group_sums.size() == f.m_pixels.size() * size_t(groups));
    f.m_groups = groups;
    f.m_group_sums = std::move(group_sums);
    return f;
}

void Film::merge(const Film& other) {
    assert(other.m_width == m_width && other.m_height == m_height);
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        FilmPixel& a = m_pixels[i];
        const FilmPixel& b = other.m_pixels[i];
        for (int c = 0; c < 3; ++c) {
            a.sum[c] += b.sum[c];
            a.sum_sq[c] += b.sum_sq[c];
            a.sum_even[c] += b.sum_even[c];
        }
        a.n += b.n;
        a.n_even += b.n_even;
    }
    assert(other.m_groups == m_groups);
    for (size_t i = 0; i < m_group_sums.size() && i < other.m_group_sums.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            m_group_sums[i].sum[c] += other.m_group_sums[i].sum[c];
            m_group_sums[i].sum_sq[c] += other.m_group_sums[i].sum_sq[c];
            m_group_sums[i].sum_even[c] += other.m_group_sums[i].sum_even[c];
        }
}

void Film::mean_into(Image& out) const {
    if (out.width != m_width || out.height != m_height) out = Image(m_width, m_height);
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const FilmPixel& px = m_pixels[i];
        const double inv = px.n ? 1.0 / px.n : 0.0;
        for (int c = 0; c < 3; ++c) out.rgb[i * 3 + c] = static_cast<float>(px.sum[c] * inv);
    }
}

Image Film::mean() const {
    Image out(m_width, m_height);
    mean_into(out);
    return out;
}

Image Film::variance_of_mean() const {
    Image out(m_width, m_height);
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const FilmPixel& px = m_pixels[i];
        for (int c = 0; c < 3; ++c) {
            const double v = px.n > 1 ? px.sample_variance(c) / px.n : 0.0;
            out.rgb[i * 3 + c] = static_cast<float>(v);
        }
    }
    return out;
}

std::optional<double> pixel_rel_mse(const FilmPixel& px) {
    if (px.n_even == 0 || px.n_odd() == 0) return std::nullopt;
    double acc = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double a = px.even_mean(c), b = px.odd_mean(c), m = px.mean(c);
        acc += 0.25 * (a - b) * (a - b) / (m * m + 0.01);
    }
    return acc / 3.0;
}

double Film::views_into(std::vector<float>& rgb, std::vector<float>& rel_error, std::vector<float>& samples) const {
    const size_t n = m_pixels.size();
    rgb.resize(n * 3);
    rel_error.resize(n);
    samples.resize(n);
    double acc = 0.0;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        const FilmPixel& px = m_pixels[i];
        const double inv = px.n ? 1.0 / px.n : 0.0;
        for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = static_cast<float>(px.sum[c] * inv);
        const std::optional<double> e = pixel_rel_mse(px);
        rel_error[i] = e ? static_cast<float>(std::sqrt(*e)) : 0.f;
        samples[i] = static_cast<float>(px.n);
        if (e) {
            acc += *e;
            ++count;
        }
    }
    return count ? acc / double(count) : 0.0;
}

double Film::estimated_rel_mse() const {
    double acc = 0.0;
    size_t count = 0;
    for (const FilmPixel& px : m_pixels)
        if (const std::optional<double> e = pixel_rel_mse(px)) {
            acc += *e;
            ++count;
        }
    return count ? acc / double(count) : 0.0;
}

double Film::mean_count() const {
    double acc = 0.0;
    for (const FilmPixel& px : m_pixels) acc += double(px.n);
    return m_pixels.empty() ? 0.0 : acc / double(m_pixels.size());
}

}  // namespace pv
