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

// One light group's sums in one pixel (core/render/light_groups.h): the samples' contributions from that group's
// lights, over the pixel's accepted samples (FilmPixel::n, n_even).
struct GroupSums {
    double sum[3] = {0, 0, 0};
    double sum_sq[3] = {0, 0, 0};
    double sum_even[3] = {0, 0, 0};
};

// Per-group gains (linear RGB multipliers, >= 0): the mixed image is the sum over groups of gain x group.
using LightGains = std::vector<vec3>;
// True when every gain is 1 (the mix is the image itself); an empty list is the identity.
inline bool gains_identity(const LightGains& gains) {
    return std::all_of(gains.begin(), gains.end(), [](vec3 k) { return k == vec3(1.f); });
}

// One pixel's term of Film::estimated_rel_mse(), averaged over channels; nothing while a half buffer is empty.
std::optional<double> pixel_rel_mse(const FilmPixel& px);

class Film {
public:
    Film() = default;
    Film(int width, int height) { reset(width, height); }
    // Clears every sum (the light groups' too, keeping their count).
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
    // The same, with the sample's radiance per light group (groups() entries, summing to L) when the film keeps
    // groups; a dropped sample counts in none of them.
    bool add(int x, int y, uint32_t index, vec3 L, const vec3* group_L) {
        if (!add(x, y, index, L)) return false;
        if (m_groups > 0) [[unlikely]]
            add_groups(size_t(y) * size_t(m_width) + size_t(x), (index & 1u) == 0u, group_L);
        return true;
    }

    // ---- Light groups (core/render/light_groups.h). Without them (the default) the film is the image alone.
    // Keeps per-group sums for `count` groups (0 or 1: none, no memory) and clears them.
    void set_groups(int count);
    int groups() const { return m_groups; }
    // Group g's sums in pixel i (row-major index).
    const GroupSums& group(size_t i, int g) const { return m_group_sums[i * size_t(m_groups) + size_t(g)]; }
    const std::vector<GroupSums>& group_sums() const { return m_group_sums; }
    std::vector<GroupSums>& mutable_group_sums() { return m_group_sums; }
    // Group g's mean image (each pixel's group sum over its sample count).
    Image group_mean(int g) const;
    // The film of the mixed image: sums and half-buffer sums exactly those of sum over groups of gain x group,
    // computed as the image's own plus (gain - 1) x group, so that with every gain 1 (or no groups, or fewer gains
    // than groups: the missing ones are 1) it is this film's, bit for bit. The sum of squares mixes each group's own
    // square by gain^2 and scales the cross terms between groups (which the film does not keep) by the mix's ratio
    // to the image: exact with every gain 1 or when no sample reaches two groups. No groups in the result.
    void mixed_into(const LightGains& gains, Film& out) const;
    Film mixed(const LightGains& gains) const {
        Film out;
        mixed_into(gains, out);
        return out;
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
    // With light groups: `groups` (> 1) sums per pixel, width * height * groups of them, pixel-major.
    static Film from_pixels(int width, int height, std::vector<FilmPixel> pixels, int groups,
                            std::vector<GroupSums> group_sums);
    // Adds another film's sums, sums of squares, half-buffer sums and counts, pixel by pixel: the film of the
    // union of both films' samples when they hold disjoint sample indices. Same size and group count; not
    // thread-safe.
    void merge(const Film& other);

private:
    void add_groups(size_t i, bool even, const vec3* group_L);
    int m_width = 0, m_height = 0;
    std::vector<FilmPixel> m_pixels;
    int m_groups = 0;                     // light groups kept (0: none)
    std::vector<GroupSums> m_group_sums;  // m_groups per pixel, pixel-major
};

}  // namespace pv
