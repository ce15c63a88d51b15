// core/image/film.h: per-pixel accumulation of radiance samples in double precision (a float running sum stalls at
// 2^24 ulps: float accumulation loses samples past that). Each pixel keeps the sum, the sum of squares (per channel)
// and the sum of its even-indexed samples, so a reference-free error estimate can compare the even and odd half-buffers
// (which must be independent estimators: both samplers guarantee it, core/sampling/sampler.h).
#pragma once

#include <algorithm>
#include <atomic>
#include <optional>
#include <vector>

#include "core/base/math.h"

namespace pv {

// One pixel's sums. The statistics below are the only place they are turned into means and variances (the film's
// views, the AOV layers, NFOR's half buffers); each needs the counts its comment says.
struct FilmPixel {
    double sum[3] = {0, 0, 0};
    double sum_sq[3] = {0, 0, 0};
    double sum_even[3] = {0, 0, 0};
    uint32_t n = 0;       // accepted samples
    uint32_t n_even = 0;  // of which even-indexed

    uint32_t n_odd() const { return n - n_even; }
    double mean(int c) const { return sum[c] / n; }                            // n > 0
    double even_mean(int c) const { return sum_even[c] / n_even; }             // n_even > 0
    double odd_mean(int c) const { return (sum[c] - sum_even[c]) / n_odd(); }  // n_odd() > 0
    // The unbiased sample variance of channel c, pooled over both halves (they estimate the same mean); n > 1.
    double sample_variance(int c) const {
        const double m = mean(c);
        return std::max(0.0, (sum_sq[c] - n * m * m) / (n - 1));
    }
};

// A linear RGB float image, row-major from the top-left, 3 floats per pixel.
struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;
    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.f) {}
    vec3 at(int x, int y) const {
        const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
        return vec3(rgb[i], rgb[i + 1], rgb[i + 2]);
    }
    void set(int x, int y, vec3 c) {
        const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
        rgb[i] = c.x;
        rgb[i + 1] = c.y;
        rgb[i + 2] = c.z;
    }
};

// One pixel's term of Film::estimated_rel_mse(), averaged over channels; nothing while a half buffer is empty.
std::optional<double> pixel_rel_mse(const FilmPixel& px);

class Film {
public:
    Film() = default;
    Film(int width, int height) { reset(width, height); }
    void reset(int width, int height);

    int width() const { return m_width; }
    int height() const { return m_height; }

    // Adds sample `index` of pixel (x, y). Returns false (and counts nothing into the pixel) if L is not finite
    // or negative: the caller counts the drop. Not thread-safe for the same pixel; pixels are owned by tiles.
    bool add(int x, int y, uint32_t index, vec3 L) {
        if (!is_finite(L) || L.x < 0.f || L.y < 0.f || L.z < 0.f) return false;
        FilmPixel& px = m_pixels[size_t(y) * size_t(m_width) + size_t(x)];
        const bool even = (index & 1u) == 0u;
        for (int c = 0; c < 3; ++c) {
            const double v = L[c];
            px.sum[c] += v;
            px.sum_sq[c] += v * v;
            if (even) px.sum_even[c] += v;
        }
        px.n++;
        px.n_even += even ? 1u : 0u;
        return true;
    }

    // Starts loading pixel (x, y)'s accumulators for add(): a pass touches each pixel once, so on a large film
    // they are a cache miss, which this overlaps with the sample's tracing. No effect on results.
    void prefetch(int x, int y) const {
        const char* p = reinterpret_cast<const char*>(&m_pixels[size_t(y) * size_t(m_width) + size_t(x)]);
        __builtin_prefetch(p, 1);
        __builtin_prefetch(p + sizeof(FilmPixel) - 1, 1);  // a pixel may straddle two cache lines
    }

    const FilmPixel& pixel(int x, int y) const { return m_pixels[size_t(y) * size_t(m_width) + size_t(x)]; }
    // The mean of each pixel (0 where no sample landed).
    Image mean() const;
    void mean_into(Image& out) const;
    // Per-pixel variance of the mean (sample variance / n), averaged over channels.
    Image variance_of_mean() const;
    // Reference-free estimate of the relative MSE of the mean image: from the even and odd half-buffer means
    // A and B, the error of their average is estimated by ((A - B)/2)^2, relative to (mean^2 + 0.01).
    double estimated_rel_mse() const;
    // Accepted samples per pixel, averaged over the image.
    double mean_count() const;
    // What the viewer shows, in one pass over the pixels: the mean RGB (3 floats a pixel), each pixel's relative
    // RMS error (the square root of pixel_rel_mse(), 0 while a half buffer is empty) and accepted sample count.
    // Resizes the vectors; returns estimated_rel_mse().
    double views_into(std::vector<float>& rgb, std::vector<float>& rel_error, std::vector<float>& samples) const;

    // The per-pixel accumulators, row-major from the top-left (for writing partial renders, core/partial/partial.h).
    const std::vector<FilmPixel>& pixels() const { return m_pixels; }
    std::vector<FilmPixel>& mutable_pixels() { return m_pixels; }  // e.g. AdaptiveMask::combine; same size
    // A film holding these accumulators (width * height of them), e.g. read back from a partial render.
    static Film from_pixels(int width, int height, std::vector<FilmPixel> pixels);
    // Adds another film's sums, sums of squares, half-buffer sums and counts, pixel by pixel: the film of the
    // union of both films' samples when they hold disjoint sample indices. Same size; not thread-safe.
    void merge(const Film& other);

private:
    int m_width = 0, m_height = 0;
    std::vector<FilmPixel> m_pixels;
};

}  // namespace pv
