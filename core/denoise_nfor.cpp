// core/denoise_nfor.cpp: cross-filtered first-order regression with per-pixel bandwidth selection (see the header).
#include "core/denoise_nfor.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>

#include "core/denoise_atrous.h"
#include "core/parallel.h"

namespace pv {
namespace {

constexpr int kRadius = 5;        // regression window 11 x 11
constexpr int kCols = 10;         // 1, albedo (3), normal (3), depth, dx, dy
constexpr int kSelectRadius = 3;  // the error maps are box-smoothed over 7 x 7 before the per-pixel choice
// Colour bandwidths k of the NL-means-style weight exp(-max(0, d2 - (v_p + v_q)) / (k^2 (v_p + v_q))) on the
// guiding half's colours (Rousselle et al. 2012's pixel distance with variance cancellation).
constexpr float kBandwidths[] = {0.5f, 1.f, 2.f};
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
            const uint32_t na = px.n_even, nb = px.n - px.n_even;
            if (na < 2 || nb < 2) continue;
            for (int c = 0; c < 3; ++c) {
                const double ma = px.sum_even[c] / na, mb = (px.sum[c] - px.sum_even[c]) / nb, m = px.sum[c] / px.n;
                p.a[size_t(i)][c] = float(ma);
                p.b[size_t(i)][c] = float(mb);
                // Each half's variance of its mean from the pooled sample variance (halves estimate the same mean).
                const double s2 = std::max(0.0, (px.sum_sq[c] - px.n * m * m) / (px.n - 1));
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

// Filters `target` by weighted first-order regression; weights from `guide` (var_g).
void regress(const Planes& p, const FeatureImage& f, const std::vector<vec3>& target, const std::vector<vec3>& guide,
             const std::vector<vec3>& var_g, float k, std::vector<vec3>& out) {
    const int w = p.w, h = p.h;
    out.assign(target.size(), vec3(0.f));
    const std::vector<float> sv = smoothed_variance(w, h, var_g), floor = variance_floor(w, h, var_g);
    parallel_for_range(0, h, [&](const tbb::blocked_range<int>& rows) {
        Eigen::Matrix<double, kCols, kCols> xtx;
        Eigen::Matrix<double, kCols, 3> xty;
        Eigen::Matrix<double, kCols, 1> row;
        for (int y = rows.begin(); y != rows.end(); ++y)
            for (int x = 0; x < w; ++x) {
                const size_t i = size_t(y) * size_t(w) + size_t(x);
                xtx.setZero();
                xty.setZero();
                const vec3 gi = guide[i], vi = var_g[i];
                const float zi = std::max(f.depth[i], 1e-6f);
                const float v_centre = std::max({sv[i], (vi.x + vi.y + vi.z) / 3.f, floor[i]});
                for (int dy = -kRadius; dy <= kRadius; ++dy) {
                    const int yy = y + dy;
                    if (yy < 0 || yy >= h) continue;
                    for (int dx = -kRadius; dx <= kRadius; ++dx) {
                        const int xx = x + dx;
                        if (xx < 0 || xx >= w) continue;
                        const size_t j = size_t(yy) * size_t(w) + size_t(xx);
                        // Colour distance on the guide half, its noise cancelled (mean over channels).
                        float dc = 0.f;
                        for (int c = 0; c < 3; ++c) {
                            const float v = std::max(vi[c] + var_g[j][c], floor[i] + floor[j]);
                            const float d2 = sqr(gi[c] - guide[j][c]);
                            dc += std::max(0.f, d2 - v) / (k * k * v + 1e-4f);
                        }
                        const vec3 da = f.albedo[j] - f.albedo[i], dn = f.normal[j] - f.normal[i];
                        const float dz = (f.depth[j] - f.depth[i]) / zi;
                        const float df = glm::dot(da, da) / sqr(kAlbedoScale) + glm::dot(dn, dn) / sqr(kNormalScale) +
                                         sqr(dz / kDepthScale);
                        // A neighbour much noisier than this pixel (its own variance or its median, whichever is
                        // larger) is down-weighted by the variance ratio (inverse-variance weighting, capped at 1): a
                        // pixel straddling a lamp's edge has a large variance that the colour distance's variance
                        // cancellation would otherwise accept as "similar".
                        const float vj = std::max({sv[j], (var_g[j].x + var_g[j].y + var_g[j].z) / 3.f, floor[j]});
                        const float vr = std::min(1.f, (v_centre + 1e-6f) / (vj + 1e-6f));
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
    });
}

// Per-pixel MSE estimate of `filtered` (from one half) against the other half `other` (variance var_o), summed
// over channels and box-smoothed.
std::vector<float> error_map(int w, int h, const std::vector<vec3>& filtered, const std::vector<vec3>& other,
                             const std::vector<vec3>& var_o) {
    std::vector<float> e(filtered.size()), s(filtered.size());
    for (size_t i = 0; i < e.size(); ++i) {
        const vec3 d = filtered[i] - other[i];
        const vec3 m = 0.5f * (filtered[i] + other[i]);  // demodulated: the relative error of the colour
        e[i] = (glm::dot(d, d) - (var_o[i].x + var_o[i].y + var_o[i].z)) / (glm::dot(m, m) + 0.01f);
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float acc = 0.f;
            int n = 0;
            for (int yy = std::max(0, y - kSelectRadius); yy <= std::min(h - 1, y + kSelectRadius); ++yy)
                for (int xx = std::max(0, x - kSelectRadius); xx <= std::min(w - 1, x + kSelectRadius); ++xx, ++n)
                    acc += e[size_t(yy) * size_t(w) + size_t(xx)];
            s[size_t(y) * size_t(w) + size_t(x)] = acc / float(n);
        }
    return s;
}

}  // namespace

Image denoise_nfor(const Film& film, const FeatureImage& features, NforStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    const Planes p = halves(film, features);
    const int w = p.w, h = p.h;
    const size_t n = size_t(w) * size_t(h);
    constexpr int kK = int(std::size(kBandwidths));
    std::vector<vec3> best(n, vec3(0.f));
    std::vector<float> best_err(n, std::numeric_limits<float>::infinity());
    std::vector<int> chosen(kK + 1, 0), choice(n, 0);
    std::vector<vec3> fa, fb;
    auto keep_better = [&](int k) {
        const std::vector<float> ea = error_map(w, h, fa, p.b, p.var_b), eb = error_map(w, h, fb, p.a, p.var_a);
        for (size_t i = 0; i < n; ++i) {
            const float e = ea[i] + eb[i];
            if (e < best_err[i]) {
                best_err[i] = e;
                best[i] = 0.5f * (fa[i] + fb[i]);
                choice[i] = k;
            }
        }
    };
    for (int k = 0; k < kK; ++k) {
        regress(p, features, p.a, p.b, p.var_b, kBandwidths[k], fa);  // half A, weights from B
        regress(p, features, p.b, p.a, p.var_a, kBandwidths[k], fb);  // half B, weights from A
        keep_better(k);
    }
    {
        // One more candidate: the interactive a-trous filter (core/denoise_atrous.h) of each half, guided by that
        // half's own colours and variance, so it is independent of the other half and its error estimate is
        // unbiased. Its 31 x 31 footprint wins where the 11 x 11 regression window cannot average enough: dim,
        // sky-lit interiors at 16 spp (Sponza: 5.0e-3 -> 3.5e-3, docs/denoise.md).
        AtrousDenoiser atrous;
        atrous.set_features(features);
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
            for (size_t i = 0; i < n; ++i)
                f[i] = filtered.at(int(i % size_t(w)), int(i / size_t(w))) / demodulation(features, i);
        }
        keep_better(kK);
    }
    Image out = film.mean();
    for (int y = 0, i = 0; y < h; ++y)
        for (int x = 0; x < w; ++x, ++i) {
            const FilmPixel& px = film.pixel(x, y);
            if (px.n_even < 2 || px.n - px.n_even < 2) continue;
            out.set(x, y, best[size_t(i)] * demodulation(features, size_t(i)));
            chosen[size_t(choice[size_t(i)])]++;
        }
    if (stats) {
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        stats->bandwidths = kK + 1;
        stats->chosen = chosen;
    }
    return out;
}

}  // namespace pv
