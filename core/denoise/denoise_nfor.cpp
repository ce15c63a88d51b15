// core/denoise/denoise_nfor.cpp: cross-filtered first-order regression with per-pixel bandwidth selection (see the
// header).
#include "core/denoise/denoise_nfor.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>

#include "core/base/parallel.h"
#include "core/denoise/denoise_atrous.h"

namespace pv {
namespace {

constexpr int kRadius = 5;  // regression window 11 x 11
constexpr int kCols = 10;   // 1, albedo (3), normal (3), depth, dx, dy
// The error maps are box-smoothed over 17 x 17 before the per-pixel choice: at 7 x 7 the estimate's noise picked a
// worse regression over the a-trous candidates at a tenth of the sunlit room's pixels (docs/denoise.md).
constexpr int kSelectRadius = 8;
// Colour bandwidths k of the NL-means-style weight exp(-max(0, d2 - (v_p + v_q)) / (k^2 (v_p + v_q))) on the
// guiding half's colours (Rousselle et al. 2012's pixel distance with variance cancellation).
constexpr float kBandwidths[] = {0.5f, 1.f, 2.f};
// The a-trous candidates' edge stops (AtrousDenoiser's sigma_colour, sigma_depth): the viewer's (4, 0.02), wider
// colour stops that average more where 4 standard deviations keep noise (dim, sky-lit interiors at 16 spp), and
// none but the normals' (the arches' edges of Sponza, whose pixels' averaged first-hit depths match neither side).
struct AtrousStops {
    float colour, depth;
};
constexpr AtrousStops kAtrousStops[] = {{4.f, 0.02f}, {16.f, 0.02f}, {64.f, 0.02f}, {1e6f, 1e6f}};
// Feature kernel scales: albedo and normal differences and relative depth at which a neighbour weighs exp(-1).
constexpr float kAlbedoScale = 0.1f, kNormalScale = 0.3f, kDepthScale = 0.05f;

struct Planes {
    int w = 0, h = 0;
    std::vector<vec3> a, b, var_a, var_b;  // half means and their variances
};

// The albedo a pixel's colour is divided by before filtering and multiplied by after (1 where nothing was hit).
vec3 demodulation(const FeatureImage& f, size_t i) {
    return f.depth[i] == 0.f ? vec3(1.f) : glm::max(f.albedo[i], vec3(1e-3f));
}

// The half means and their variances, divided by the albedo: texture detail is then not noise to the filter.
Planes halves(const Film& film, const FeatureImage& f) {
    Planes p;
    p.w = film.width();
    p.h = film.height();
    const size_t n = size_t(p.w) * size_t(p.h);
    p.a.assign(n, vec3(0.f));
    p.b = p.var_a = p.var_b = p.a;
    for (int y = 0, i = 0; y < p.h; ++y)
        for (int x = 0; x < p.w; ++x, ++i) {
            const FilmPixel& px = film.pixel(x, y);
            const uint32_t na = px.n_even, nb = px.n_odd();
            if (na < 2 || nb < 2) continue;
            for (int c = 0; c < 3; ++c) {
                p.a[size_t(i)][c] = float(px.even_mean(c));
                p.b[size_t(i)][c] = float(px.odd_mean(c));
                // Each half's variance of its mean from the pooled sample variance (halves estimate the same mean).
                const double s2 = px.sample_variance(c);
                p.var_a[size_t(i)][c] = float(s2 / na);
                p.var_b[size_t(i)][c] = float(s2 / nb);
            }
            const vec3 d = demodulation(f, size_t(i));
            p.a[size_t(i)] /= d;
            p.b[size_t(i)] /= d;
            p.var_a[size_t(i)] /= d * d;
            p.var_b[size_t(i)] /= d * d;
        }
    return p;
}

// Mean over channels of `var`, then the median over 3 x 3: steadier than one pixel's 8-sample estimate, and unlike
// a box mean not raised by a neighbouring row of noisy edge pixels.
std::vector<float> smoothed_variance(int w, int h, const std::vector<vec3>& var) {
    std::vector<float> s(var.size(), 0.f);
    float win[9];
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int n = 0;
            for (int yy = std::max(0, y - 1); yy <= std::min(h - 1, y + 1); ++yy)
                for (int xx = std::max(0, x - 1); xx <= std::min(w - 1, x + 1); ++xx) {
                    const vec3 v = var[size_t(yy) * size_t(w) + size_t(xx)];
                    win[n++] = (v.x + v.y + v.z) / 3.f;
                }
            std::nth_element(win, win + n / 2, win + n);
            s[size_t(y) * size_t(w) + size_t(x)] = win[n / 2];
        }
    return s;
}

// A floor for a pixel's variance: a quarter of the 5 x 5 box mean. A pixel whose few samples all agreed (all zero
// in a dark corner) has variance 0, and would otherwise accept no neighbour at all and stay black.
std::vector<float> variance_floor(int w, int h, const std::vector<vec3>& var) {
    std::vector<float> s(var.size(), 0.f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float acc = 0.f;
            int n = 0;
            for (int yy = std::max(0, y - 2); yy <= std::min(h - 1, y + 2); ++yy)
                for (int xx = std::max(0, x - 2); xx <= std::min(w - 1, x + 2); ++xx, ++n) {
                    const vec3 v = var[size_t(yy) * size_t(w) + size_t(xx)];
                    acc += (v.x + v.y + v.z) / 3.f;
                }
            s[size_t(y) * size_t(w) + size_t(x)] = 0.25f * acc / float(n);
        }
    return s;
}

// What a pixel's colour weights compare its neighbours with. Cross-filtered (weights from half B for filtering
// half A) with B's own colour at the centre, the filtered pixel still depends on B's noise at that pixel, and scored
// against B there it looks better than it is (E|fA - B|^2 = MSE(fA) + Var(B) - 2 Cov(fA, B)), most for the
// narrowest bandwidth: scored so, it is chosen at 82% of the sunlit room's pixels at 16 spp although the a-trous
// candidate has 3x less error. So the centre's guide colour, its noise variance and its variance scale come from its
// eight neighbours only (the mean of their colours, the variance of that mean, the median of their variances), and the
// centre pixel's own weight from the features only: the filtered pixel is then independent of the guide's noise at
// that pixel (up to the pooled variances of its neighbours, which carry both halves' samples), so that
// E|fA - B|^2 - Var(B) = MSE(fA), and the same filter is the output (it is no worse than the guide's own centre).
struct Centres {
    std::vector<vec3> colour, noise;  // guide colour and the variance of its noise per channel
    std::vector<float> scale;         // the variance the neighbours' variance is compared with (vr below)
    std::vector<float> floor;         // the centre's variance floor
};

// The feature part of a neighbour's weight, exp(-feature_distance): albedo and normal differences, relative depth.
float feature_distance(const FeatureImage& f, size_t i, size_t j) {
    const vec3 da = f.albedo[j] - f.albedo[i], dn = f.normal[j] - f.normal[i];
    const float dz = (f.depth[j] - f.depth[i]) / std::max(f.depth[i], 1e-6f);
    return glm::dot(da, da) / sqr(kAlbedoScale) + glm::dot(dn, dn) / sqr(kNormalScale) + sqr(dz / kDepthScale);
}

Centres centres(int w, int h, const FeatureImage& f, const std::vector<vec3>& guide, const std::vector<vec3>& var_g) {
    Centres c;
    c.colour.assign(guide.size(), vec3(0.f));
    c.noise = c.colour;
    c.scale.assign(guide.size(), 0.f);
    c.floor = c.scale;
    float win[8];
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * size_t(w) + size_t(x);
            // The neighbours' colours weighted by their feature similarity (a lamp's pixels do not set the colour
            // of the ceiling pixel beside it); their plain mean where none is similar.
            vec3 m(0.f), v(0.f), pm(0.f), pv(0.f);
            float ws = 0.f;
            int n = 0;
            for (int yy = std::max(0, y - 1); yy <= std::min(h - 1, y + 1); ++yy)
                for (int xx = std::max(0, x - 1); xx <= std::min(w - 1, x + 1); ++xx) {
                    const size_t j = size_t(yy) * size_t(w) + size_t(xx);
                    if (j == i) continue;
                    const float wj = std::exp(-feature_distance(f, i, j));
                    m += wj * guide[j];
                    v += wj * wj * var_g[j];
                    ws += wj;
                    pm += guide[j];
                    pv += var_g[j];
                    win[n++] = (var_g[j].x + var_g[j].y + var_g[j].z) / 3.f;
                }
            std::nth_element(win, win + n / 2, win + n);
            if (ws > 1e-3f) {
                c.colour[i] = m / ws;
                c.noise[i] = v / (ws * ws);
            } else {
                c.colour[i] = pm / float(n);
                c.noise[i] = pv / float(n * n);
            }
            // The 5 x 5 floor without the centre: 25 floor = 0.25 (sum of 25) -> 0.25 (sum of 24) / 24.
            float acc = 0.f;
            int k = 0;
            for (int yy = std::max(0, y - 2); yy <= std::min(h - 1, y + 2); ++yy)
                for (int xx = std::max(0, x - 2); xx <= std::min(w - 1, x + 2); ++xx) {
                    const size_t j = size_t(yy) * size_t(w) + size_t(xx);
                    if (j == i) continue;
                    acc += (var_g[j].x + var_g[j].y + var_g[j].z) / 3.f;
                    ++k;
                }
            c.floor[i] = 0.25f * acc / float(k);
            c.scale[i] = std::max(win[n / 2], c.floor[i]);
        }
    return c;
}

// Filters `target` by weighted first-order regression; weights from `guide` (var_g), its centres as above.
void regress(const Planes& p, const FeatureImage& f, const std::vector<vec3>& target, const std::vector<vec3>& guide,
             const std::vector<vec3>& var_g, float k, std::vector<vec3>& out, const std::atomic<bool>* cancel) {
    const int w = p.w, h = p.h;
    out.assign(target.size(), vec3(0.f));
    const std::vector<float> sv = smoothed_variance(w, h, var_g), floor = variance_floor(w, h, var_g);
    const Centres cen = centres(w, h, f, guide, var_g);
    parallel_for_range(0, h, [&](const tbb::blocked_range<int>& rows) {
        Eigen::Matrix<double, kCols, kCols> xtx;
        Eigen::Matrix<double, kCols, 3> xty;
        Eigen::Matrix<double, kCols, 1> row;
        for (int y = rows.begin(); y != rows.end(); ++y) {
            if (cancel && cancel->load(std::memory_order_relaxed)) return;
            for (int x = 0; x < w; ++x) {
                const size_t i = size_t(y) * size_t(w) + size_t(x);
                xtx.setZero();
                xty.setZero();
                const vec3 gi = cen.colour[i], vi = cen.noise[i];
                const float zi = std::max(f.depth[i], 1e-6f);
                const float v_centre = cen.scale[i], floor_i = cen.floor[i];
                for (int dy = -kRadius; dy <= kRadius; ++dy) {
                    const int yy = y + dy;
                    if (yy < 0 || yy >= h) continue;
                    for (int dx = -kRadius; dx <= kRadius; ++dx) {
                        const int xx = x + dx;
                        if (xx < 0 || xx >= w) continue;
                        const size_t j = size_t(yy) * size_t(w) + size_t(xx);
                        // Colour distance on the guide half, its noise cancelled (mean over channels).
                        float dc = 0.f;
                        for (int c = 0; c < 3 && j != i; ++c) {
                            const float v = std::max(vi[c] + var_g[j][c], floor_i + floor[j]);
                            const float d2 = sqr(gi[c] - guide[j][c]);
                            dc += std::max(0.f, d2 - v) / (k * k * v + 1e-4f);
                        }
                        const vec3 da = f.albedo[j] - f.albedo[i], dn = f.normal[j] - f.normal[i];
                        const float dz = (f.depth[j] - f.depth[i]) / zi;
                        const float df = feature_distance(f, i, j);
                        // A neighbour much noisier than this pixel (its own variance or its median, whichever is
                        // larger) is down-weighted by the variance ratio (inverse-variance weighting, capped at 1): a
                        // pixel straddling a lamp's edge has a large variance that the colour distance's variance
                        // cancellation would otherwise accept as "similar".
                        const float vj = std::max({sv[j], (var_g[j].x + var_g[j].y + var_g[j].z) / 3.f, floor[j]});
                        const float vr = j == i ? 1.f : std::min(1.f, (v_centre + 1e-6f) / (vj + 1e-6f));
                        const double wgt = vr * std::exp(-double(dc) / 3.0 - double(df));
                        if (wgt < 1e-6) continue;
                        row << 1.0, da.x, da.y, da.z, dn.x, dn.y, dn.z, dz, dx / double(kRadius), dy / double(kRadius);
                        xtx.selfadjointView<Eigen::Upper>().rankUpdate(row, wgt);
                        const vec3 t = target[j];
                        xty.col(0) += wgt * t.x * row;
                        xty.col(1) += wgt * t.y * row;
                        xty.col(2) += wgt * t.z * row;
                    }
                }
                // Ridge term relative to each column's own scale (so a feature that varies little, like the albedo
                // of a pixel partly covering a lamp, keeps its slope), plus a tiny absolute one for features that
                // are constant over the window (one flat wall), whose columns are zero.
                Eigen::Matrix<double, kCols, kCols> m = xtx.selfadjointView<Eigen::Upper>();
                const double tiny = 1e-8 * std::max(m(0, 0), 1e-12);
                for (int c = 1; c < kCols; ++c) m(c, c) += 1e-3 * m(c, c) + tiny;
                const Eigen::Matrix<double, kCols, 3> beta = m.ldlt().solve(xty);
                vec3 o(float(beta(0, 0)), float(beta(0, 1)), float(beta(0, 2)));
                if (!is_finite(o)) o = target[i];
                out[i] = glm::max(o, vec3(0.f));
            }
        }
    });
}

// Per-pixel MSE estimate of `filtered` (from one half) against the other half `other` (variance var_o), summed
// over channels, relative to `scale` (|c|^2 + 0.01 of a colour c independent of `other`, the same for every
// candidate), and box-smoothed.
std::vector<float> error_map(int w, int h, const std::vector<vec3>& filtered, const std::vector<vec3>& other,
                             const std::vector<vec3>& var_o, const std::vector<float>& scale) {
    std::vector<float> e(filtered.size()), s(filtered.size());
    for (size_t i = 0; i < e.size(); ++i) {
        const vec3 d = filtered[i] - other[i];
        e[i] = (glm::dot(d, d) - (var_o[i].x + var_o[i].y + var_o[i].z)) / scale[i];
    }
    // Box mean, separable: rows into `s`, then columns back into `e` (double sums: 17 x 17 of mixed signs).
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double acc = 0.0;
            const int x0 = std::max(0, x - kSelectRadius), x1 = std::min(w - 1, x + kSelectRadius);
            for (int xx = x0; xx <= x1; ++xx) acc += e[size_t(y) * size_t(w) + size_t(xx)];
            s[size_t(y) * size_t(w) + size_t(x)] = float(acc / (x1 - x0 + 1));
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double acc = 0.0;
            const int y0 = std::max(0, y - kSelectRadius), y1 = std::min(h - 1, y + kSelectRadius);
            for (int yy = y0; yy <= y1; ++yy) acc += s[size_t(yy) * size_t(w) + size_t(x)];
            e[size_t(y) * size_t(w) + size_t(x)] = float(acc / (y1 - y0 + 1));
        }
    return e;
}

// The a-trous filter (core/denoise/denoise_atrous.h) of each half, guided by that half's own colours and variance;
// `atrous` has the features set.
void atrous_halves(const Planes& p, const FeatureImage& features, AtrousDenoiser& atrous, std::vector<vec3>& fa,
                   std::vector<vec3>& fb) {
    const int w = p.w, h = p.h;
    const size_t n = size_t(w) * size_t(h);
    Image mean(w, h), var(w, h), filtered;
    for (int half = 0; half < 2; ++half) {
        const std::vector<vec3>&m = half == 0 ? p.a : p.b, &v = half == 0 ? p.var_a : p.var_b;
        for (size_t i = 0; i < n; ++i) {
            const vec3 d = demodulation(features, i);
            for (int c = 0; c < 3; ++c) {
                mean.rgb[i * 3 + size_t(c)] = m[i][c] * d[c];
                var.rgb[i * 3 + size_t(c)] = v[i][c] * d[c] * d[c];
            }
        }
        atrous.denoise(mean, var, filtered);
        std::vector<vec3>& f = half == 0 ? fa : fb;
        f.resize(n);
        for (size_t i = 0; i < n; ++i)
            f[i] = filtered.at(int(i % size_t(w)), int(i / size_t(w))) / demodulation(features, i);
    }
}

}  // namespace

Image denoise_nfor(const Film& film, const FeatureImage& features, NforStats* stats, const std::atomic<bool>* cancel) {
    const auto cancelled = [cancel] { return cancel && cancel->load(std::memory_order_relaxed); };
    const auto start = std::chrono::steady_clock::now();
    const Planes p = halves(film, features);
    const int w = p.w, h = p.h;
    const size_t n = size_t(w) * size_t(h);
    constexpr int kK = int(std::size(kBandwidths)), kT = int(std::size(kAtrousStops));
    std::vector<vec3> best(n, vec3(0.f));
    std::vector<float> best_err(n, std::numeric_limits<float>::infinity());
    std::vector<int> chosen(kK + kT, 0), choice(n, 0);
    // The first a-trous candidate's filtered halves (each independent of the other half) give the error maps'
    // relative scale, the same for every candidate (a scale from the compared half, as before, let a noisy bright
    // pixel of that half shrink its own error term).
    AtrousDenoiser atrous(kAtrousStops[0].colour, kAtrousStops[0].depth);
    atrous.set_features(features);
    std::vector<vec3> ta, tb;
    atrous_halves(p, features, atrous, ta, tb);
    std::vector<float> scale_a(n), scale_b(n);
    for (size_t i = 0; i < n; ++i) {
        scale_a[i] = glm::dot(ta[i], ta[i]) + 0.01f;
        scale_b[i] = glm::dot(tb[i], tb[i]) + 0.01f;
    }
    // Candidate k: filtered halves fa, fb scored against the other half; its output is `result`.
    auto keep_better = [&](int k, const std::vector<vec3>& fa, const std::vector<vec3>& fb, auto result) {
        const std::vector<float> ea = error_map(w, h, fa, p.b, p.var_b, scale_a),
                                 eb = error_map(w, h, fb, p.a, p.var_a, scale_b);
        for (size_t i = 0; i < n; ++i) {
            const float e = ea[i] + eb[i];
            if (e < best_err[i]) {
                best_err[i] = e;
                best[i] = result(i);
                choice[i] = k;
            }
        }
    };
    std::vector<vec3> fa, fb;
    for (int k = 0; k < kK; ++k) {
        regress(p, features, p.a, p.b, p.var_b, kBandwidths[k], fa, cancel);  // half A, weights from B
        regress(p, features, p.b, p.a, p.var_a, kBandwidths[k], fb, cancel);  // half B, weights from A
        if (cancelled()) return Image();
        keep_better(k, fa, fb, [&](size_t i) { return 0.5f * (fa[i] + fb[i]); });
    }
    // The a-trous candidates, scored by their filtered halves; the output is the same filter (its features laid out
    // once) of the full mean (half the variance of either half's).
    const Image mean = film.mean(), var = film.variance_of_mean();
    Image full;
    for (int t = 0; t < kT; ++t) {
        if (t > 0) {
            atrous = AtrousDenoiser(kAtrousStops[t].colour, kAtrousStops[t].depth);
            atrous.set_features(features);
            atrous_halves(p, features, atrous, ta, tb);
        }
        atrous.denoise(mean, var, full);
        keep_better(kK + t, ta, tb, [&](size_t i) {
            return full.at(int(i % size_t(w)), int(i / size_t(w))) / demodulation(features, i);
        });
    }
    if (cancelled()) return Image();
    Image out = mean;
    for (int y = 0, i = 0; y < h; ++y)
        for (int x = 0; x < w; ++x, ++i) {
            const FilmPixel& px = film.pixel(x, y);
            if (px.n_even < 2 || px.n - px.n_even < 2) continue;
            out.set(x, y, best[size_t(i)] * demodulation(features, size_t(i)));
            chosen[size_t(choice[size_t(i)])]++;
        }
    if (stats) {
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        stats->bandwidths = kK + kT;
        stats->chosen = chosen;
    }
    return out;
}

}  // namespace pv
