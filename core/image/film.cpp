// core/image/film.cpp: means, variances and the half-buffer error estimate.
#include "core/image/film.h"

#include <cassert>

namespace pv {

void Film::reset(int width, int height) {
    m_width = width;
    m_height = height;
    m_pixels.assign(size_t(width) * size_t(height), FilmPixel{});
}

Film Film::from_pixels(int width, int height, std::vector<FilmPixel> pixels) {
    assert(pixels.size() == size_t(width) * size_t(height));
    Film f;
    f.m_width = width;
    f.m_height = height;
    f.m_pixels = std::move(pixels);
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
