// core/denoise/denoise_atrous.cpp: edge-avoiding a-trous filtering (see the header).
#include "core/denoise/denoise_atrous.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/base/error.h"

// The planes a loop reads and writes do not overlap (the accumulators are a row buffer of their own): tell GCC's
// vectoriser, which otherwise gives up on the number of run-time alias checks. Not for clang (the sanitizer and
// fuzzer builds), whose assume_safety warns (-Wpass-failed, an error under -Werror) where it cannot vectorise.
#if defined(__GNUC__) && !defined(__clang__)
#define PV_NO_ALIAS_LOOP _Pragma("GCC ivdep")
#else
#define PV_NO_ALIAS_LOOP
#endif

namespace pv {
namespace {

constexpr int kPasses = 4;
// B-spline taps (1/4, 1/2, 1/4): the 3x3 kernel of the a-trous transform.
constexpr float kTap[3] = {0.25f, 0.5f, 0.25f};
// Edge-stopping parameters (SVGF, Schied et al. 2017, sec. 4.4; normal exponent 64 below): colour in standard
// deviations, depth relative to the pixel's depth; AtrousDenoiser's constructor takes them (defaults 4 and 0.02).

// The planes, in the order they are laid out.
enum Plane {
    kDemodR,
    kDemodG,
    kDemodB,
    kColR,
    kColG,
    kColB,
    kVar,
    kNx,
    kNy,
    kNz,
    kValid,
    kZ,
    kInvDz,
    kLum,
    kInvSigma,
    kTmpR,
    kTmpG,
    kTmpB,
    kTmpVar,
    kPlaneCount
};

// exp(-e) for e >= 0, approximated by max(0, 1 - e/16)^16: never negative, 0 beyond 16, no libm call.
inline float stop_weight(float e) {
    float t = std::max(0.f, 1.f - e * (1.f / 16.f));
    t *= t;
    t *= t;
    t *= t;
    return t * t;
}

// max(0, n_i . n_j)^64 by six squarings.
inline float normal_weight(float dot) {
    float wn = std::max(0.f, dot);
    wn *= wn;
    wn *= wn;
    wn *= wn;
    wn *= wn;
    wn *= wn;
    return wn * wn;
}

// One tap offset over a run of pixels of one row: the centre's planes (suffix i), the neighbour's (j), and the
// row accumulators, each pointer at the run's first pixel.
// Cloned for AVX2 where the CPU has it (an ifunc picks the version at load time). Not under the sanitizers: the ifunc
// resolver runs before ThreadSanitizer's runtime is initialised, and the TSan test binary crashed at start-up.
#if defined(PATHVIEW_SANITIZED)
#define PV_AVX2_CLONES
#else
#define PV_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#endif

struct Taps {
    const float *ni[3], *nj[3], *cj[3];
    const float *zi, *zj, *inv_dz, *li, *lj, *inv_sigma, *vj;
    float *acc[3], *acc_v, *acc_w;
};

// Cloned for AVX2 (8 floats a vector) where the CPU has it; the default SSE2 version everywhere else.
PV_AVX2_CLONES void accumulate_taps(const Taps& t, int count, float tap, float inv_stride) {
    const float *nxi = t.ni[0], *nyi = t.ni[1], *nzi = t.ni[2], *nxj = t.nj[0], *nyj = t.nj[1], *nzj = t.nj[2];
    const float *cr = t.cj[0], *cg = t.cj[1], *cb = t.cj[2], *vj = t.vj;
    const float *zi = t.zi, *zj = t.zj, *idz = t.inv_dz, *li = t.li, *lj = t.lj, *isg = t.inv_sigma;
    float *sr = t.acc[0], *sg = t.acc[1], *sb = t.acc[2], *sv = t.acc_v, *sw = t.acc_w;
    PV_NO_ALIAS_LOOP
    for (int x = 0; x < count; ++x) {
        const float wn = normal_weight(nxi[x] * nxj[x] + nyi[x] * nyj[x] + nzi[x] * nzj[x]);
        const float e = std::fabs(zj[x] - zi[x]) * idz[x] * inv_stride + std::fabs(lj[x] - li[x]) * isg[x];
        const float wgt = tap * wn * stop_weight(e);
        sr[x] += wgt * cr[x];
        sg[x] += wgt * cg[x];
        sb[x] += wgt * cb[x];
        sv[x] += wgt * wgt * vj[x];
        sw[x] += wgt;
    }
}

// The planes of one pass, for filter_interior.
struct PassPlanes {
    const float *nx, *ny, *nz, *z, *inv_dz, *lum, *inv_sigma, *valid, *col[3], *var;
    float *out[3], *out_var;
};

constexpr float kCentre = kTap[1] * kTap[1];

// Pixels i0 .. i0 + count - 1 of a row whose eight neighbours at the pass's offsets all lie in the image: all
// taps of a pixel in one loop body, its centre values and sums in registers. The same operations in the same
// order as the centre loop, accumulate_taps and the normalisation of the row path, so the result is the same bit
// for bit.
PV_AVX2_CLONES void filter_interior(const PassPlanes& p, size_t i0, int count, const ptrdiff_t (&off)[8],
                                    const float (&tap)[8], float inv_stride) {
    const float *nx = p.nx, *ny = p.ny, *nz = p.nz, *z = p.z, *idz = p.inv_dz, *lum = p.lum, *isg = p.inv_sigma;
    const float *valid = p.valid, *cr = p.col[0], *cg = p.col[1], *cb = p.col[2], *var = p.var;
    float *tr = p.out[0], *tg = p.out[1], *tb = p.out[2], *tv = p.out_var;
    PV_NO_ALIAS_LOOP
    for (int k = 0; k < count; ++k) {
        const size_t i = i0 + size_t(k);
        const float wc = kCentre * valid[i];
        float sr = wc * cr[i], sg = wc * cg[i], sb = wc * cb[i], sv = wc * wc * var[i], sw = wc;
        const float nxi = nx[i], nyi = ny[i], nzi = nz[i], zi = z[i], idzi = idz[i], li = lum[i], isgi = isg[i];
#pragma GCC unroll 8
        for (int t = 0; t < 8; ++t) {
            const size_t j = size_t(ptrdiff_t(i) + off[t]);
            const float wn = normal_weight(nxi * nx[j] + nyi * ny[j] + nzi * nz[j]);
            const float e = std::fabs(z[j] - zi) * idzi * inv_stride + std::fabs(lum[j] - li) * isgi;
            const float wgt = tap[t] * wn * stop_weight(e);
            sr += wgt * cr[j];
            sg += wgt * cg[j];
            sb += wgt * cb[j];
            sv += wgt * wgt * var[j];
            sw += wgt;
        }
        const float keep = 1.f - valid[i];
        const float inv = 1.f / (sw + keep);
        tr[i] = (sr + keep * cr[i]) * inv;
        tg[i] = (sg + keep * cg[i]) * inv;
        tb[i] = (sb + keep * cb[i]) * inv;
        tv[i] = (sv + keep * var[i]) * inv * inv;
    }
}

}  // namespace

float* AtrousDenoiser::plane(int k) { return m_planes.data() + size_t(k) * size_t(m_w) * size_t(m_h); }

void AtrousDenoiser::set_features(const FeatureImage& f) {
    const int w = f.width, h = f.height;
    const size_t n = size_t(w) * size_t(h);
    if (w != m_w || h != m_h || m_planes.size() != n * kPlaneCount) {
        m_w = w;
        m_h = h;
        m_planes.assign(n * kPlaneCount, 0.f);
        m_rows.assign(size_t(w) * 5, 0.f);
    }
    float* const dem[3] = {plane(kDemodR), plane(kDemodG), plane(kDemodB)};
    float* const nrm[3] = {plane(kNx), plane(kNy), plane(kNz)};
    float *const valid = plane(kValid), *const z = plane(kZ), *const inv_dz = plane(kInvDz);
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            dem[c][i] = f.albedo[i][c];
            nrm[c][i] = f.normal[i][c];
        }
        z[i] = f.depth[i];
    }
    // Demodulation albedo: where nothing was hit (e.g. the sky) 1, the colour itself is filtered. Unit normals: a
    // pixel across an edge has a shorter mean normal, which would scale every weight it takes. Pixels with normal
    // 0 (nothing hit) take no neighbour and are kept as they are (valid 0).
    PV_NO_ALIAS_LOOP
    for (size_t i = 0; i < n; ++i) {
        const bool hit = z[i] != 0.f;
        for (int c = 0; c < 3; ++c) dem[c][i] = hit ? std::max(dem[c][i], 1e-3f) : 1.f;
        const float l2 = nrm[0][i] * nrm[0][i] + nrm[1][i] * nrm[1][i] + nrm[2][i] * nrm[2][i];
        const float inv_l = l2 > 0.f ? 1.f / std::sqrt(l2) : 0.f;
        for (int c = 0; c < 3; ++c) nrm[c][i] *= inv_l;
        valid[i] = l2 > 0.f ? 1.f : 0.f;
        inv_dz[i] = 1.f / (m_sigma_depth * std::max(z[i], 1e-6f));
    }
}

void AtrousDenoiser::denoise(const Image& mean, const Image& variance_of_mean, const FeatureImage& features,
                             Image& out) {
    set_features(features);
    denoise(mean, variance_of_mean, out);
}

namespace {

// Demodulate: the colour divided by the albedo (irradiance-like, what is filtered); the variance of the channel mean,
// by the albedo's luminance squared.
void demodulate(const Image& mean, const Image& variance_of_mean, float* const (&dem)[3], float* const (&col)[3],
                float* var, size_t n) {
    const float *const rgb = mean.rgb.data(), *const vrgb = variance_of_mean.rgb.data();
    PV_NO_ALIAS_LOOP
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) col[c][i] = rgb[i * 3 + size_t(c)] / dem[c][i];
        const float la = 0.2126f * dem[0][i] + 0.7152f * dem[1][i] + 0.0722f * dem[2][i];
        var[i] = std::max(0.f, (vrgb[i * 3] + vrgb[i * 3 + 1] + vrgb[i * 3 + 2]) * (1.f / 3.f)) / (la * la);
    }
}

// 1 / the colour scale of each pixel, from the variance box-filtered over 3x3 (SVGF sec. 4.4): a pixel whose few
// samples all agreed (all zero, say) has variance 0 and would accept no neighbour, a black dot in the output.
// `rows` holds 2 x w floats of scratch.
void colour_scale(const float* var, float* inv_sigma, float* rows, int w, int h, float sigma_colour) {
    for (int y = 0; y < h; ++y) {
        float* const rs = rows;  // vertical sums of this row over rows y0..y1
        const int y0 = std::max(0, y - 1), y1 = std::min(h - 1, y + 1);
        std::fill(rs, rs + w, 0.f);
        for (int yy = y0; yy <= y1; ++yy) {
            const float* vr = var + size_t(yy) * size_t(w);
            for (int x = 0; x < w; ++x) rs[x] += vr[x];
        }
        float* const box = rows + w;
        box[0] = (rs[0] + (w > 1 ? rs[1] : 0.f)) / float(std::min(w, 2));
        for (int x = 1; x + 1 < w; ++x) box[x] = (rs[x - 1] + rs[x] + rs[x + 1]) * (1.f / 3.f);
        if (w > 1) box[w - 1] = (rs[w - 2] + rs[w - 1]) * 0.5f;
        const float inv_rows = 1.f / float(y1 - y0 + 1);
        float* is = inv_sigma + size_t(y) * size_t(w);
        for (int x = 0; x < w; ++x) is[x] = 1.f / (sigma_colour * std::sqrt(box[x] * inv_rows) + 1e-4f);
    }
}

// One pass's geometry: the image size, the stride of its taps, and the row accumulators (5 x w floats).
struct PassShape {
    int w, h, stride;
    float inv_stride;
    float* rows;
};

// Pixels xa .. xb - 1 of row y, tap by tap over row segments (the pixels near the border, whose taps may fall
// outside): the centre into the row accumulators, each in-image outer tap by accumulate_taps, then normalised.
void filter_row_segment(const PassPlanes& p, const PassShape& s, int y, int xa, int xb) {
    const int w = s.w;
    float* const rows = s.rows;
    float *const ar = rows, *const ag = rows + w, *const ab = rows + 2 * w, *const av = rows + 3 * w,
                 *const aw = rows + 4 * w;
    const float* const* col = p.col;
    const float *const var = p.var, *const valid = p.valid;
    const size_t ri = size_t(y) * size_t(w);
    // The centre tap: weight kTap[1]^2 (all its stopping terms are 1), 0 for an invalid pixel.
    PV_NO_ALIAS_LOOP
    for (int x = xa; x < xb; ++x) {
        const size_t i = ri + size_t(x);
        const float wc = kCentre * valid[i];
        ar[x] = wc * col[0][i];
        ag[x] = wc * col[1][i];
        ab[x] = wc * col[2][i];
        av[x] = wc * wc * var[i];
        aw[x] = wc;
    }
    const float* const nrm[3] = {p.nx, p.ny, p.nz};
    for (int ky = 0; ky < 3; ++ky) {
        const int yy = y + (ky - 1) * s.stride;
        if (yy < 0 || yy >= s.h) continue;
        for (int kx = 0; kx < 3; ++kx) {
            if (kx == 1 && ky == 1) continue;  // the centre, above
            const int dx = (kx - 1) * s.stride;
            const int x0 = std::max(xa, -dx), x1 = std::min(xb, w - dx);
            if (x1 <= x0) continue;  // a stride wider than the image
            const size_t ri0 = ri + size_t(x0), rj = size_t(yy) * size_t(w) + size_t(x0 + dx);
            Taps t;
            for (int c = 0; c < 3; ++c) {
                t.ni[c] = nrm[c] + ri0;
                t.nj[c] = nrm[c] + rj;
                t.cj[c] = col[c] + rj;
                t.acc[c] = rows + size_t(c) * size_t(w) + size_t(x0);
            }
            t.zi = p.z + ri0;
            t.zj = p.z + rj;
            t.inv_dz = p.inv_dz + ri0;
            t.li = p.lum + ri0;
            t.lj = p.lum + rj;
            t.inv_sigma = p.inv_sigma + ri0;
            t.vj = var + rj;
            t.acc_v = rows + 3 * size_t(w) + size_t(x0);
            t.acc_w = rows + 4 * size_t(w) + size_t(x0);
            accumulate_taps(t, x1 - x0, kTap[kx] * kTap[ky], s.inv_stride);
        }
    }
    // An invalid pixel has weight sum 0 (its normal 0 zeroes every tap): it keeps its colour and variance.
    float *const tr = p.out[0], *const tg = p.out[1], *const tb = p.out[2], *const tv = p.out_var;
    PV_NO_ALIAS_LOOP
    for (int x = xa; x < xb; ++x) {
        const size_t i = ri + size_t(x);
        const float keep = 1.f - valid[i];
        const float inv = 1.f / (aw[x] + keep);
        tr[i] = (ar[x] + keep * col[0][i]) * inv;
        tg[i] = (ag[x] + keep * col[1][i]) * inv;
        tb[i] = (ab[x] + keep * col[2][i]) * inv;
        tv[i] = (av[x] + keep * var[i]) * inv * inv;
    }
}

// One a-trous pass from p.col, p.var into p.out, p.out_var: rows and columns whose taps all fall inside through
// filter_interior, the rest by filter_row_segment.
void filter_pass(const PassPlanes& p, const PassShape& s) {
    const int w = s.w, h = s.h, stride = s.stride;
    // Offsets and weights of the eight outer taps, in filter_row_segment's order.
    ptrdiff_t off[8];
    float taps[8];
    for (int ky = 0, t = 0; ky < 3; ++ky)
        for (int kx = 0; kx < 3; ++kx)
            if (kx != 1 || ky != 1) {
                off[t] = ptrdiff_t(ky - 1) * stride * w + (kx - 1) * stride;
                taps[t++] = kTap[kx] * kTap[ky];
            }
    for (int y = 0; y < h; ++y) {
        const size_t ri = size_t(y) * size_t(w);
        const bool inner_row = y >= stride && y + stride < h && w > 2 * stride;
        if (inner_row) {
            filter_interior(p, ri + size_t(stride), w - 2 * stride, off, taps, s.inv_stride);
            filter_row_segment(p, s, y, 0, stride);
            filter_row_segment(p, s, y, w - stride, w);
        } else {
            filter_row_segment(p, s, y, 0, w);
        }
    }
}

}  // namespace

// Demodulate; per pass: the colour scale, the luminance, the filter (its output the next pass's input); remodulate.
void AtrousDenoiser::denoise(const Image& mean, const Image& variance_of_mean, Image& out) {
    const int w = m_w, h = m_h;
    const size_t n = size_t(w) * size_t(h);
    if (mean.width != w || mean.height != h || variance_of_mean.width != w || variance_of_mean.height != h)
        throw Error("denoise_atrous: the image is " + std::to_string(mean.width) + "x" + std::to_string(mean.height) +
                    ", the features " + std::to_string(w) + "x" + std::to_string(h));
    float* const dem[3] = {plane(kDemodR), plane(kDemodG), plane(kDemodB)};
    float* col[3] = {plane(kColR), plane(kColG), plane(kColB)};
    float* tmp[3] = {plane(kTmpR), plane(kTmpG), plane(kTmpB)};
    float *var = plane(kVar), *tmpv = plane(kTmpVar);
    float *const lum = plane(kLum), *const inv_sigma = plane(kInvSigma);
    demodulate(mean, variance_of_mean, dem, col, var, n);

    for (int pass = 0; pass < kPasses; ++pass) {
        const int stride = 1 << pass;
        colour_scale(var, inv_sigma, m_rows.data(), w, h, m_sigma_colour);
        for (size_t i = 0; i < n; ++i) lum[i] = 0.2126f * col[0][i] + 0.7152f * col[1][i] + 0.0722f * col[2][i];
        const PassPlanes pp{plane(kNx),
                            plane(kNy),
                            plane(kNz),
                            plane(kZ),
                            plane(kInvDz),
                            lum,
                            inv_sigma,
                            plane(kValid),
                            {col[0], col[1], col[2]},
                            var,
                            {tmp[0], tmp[1], tmp[2]},
                            tmpv};
        filter_pass(pp, PassShape{w, h, stride, 1.f / float(stride), m_rows.data()});
        for (int c = 0; c < 3; ++c) std::swap(col[c], tmp[c]);
        std::swap(var, tmpv);
    }
    if (out.width != w || out.height != h || out.rgb.size() != n * 3) out = Image(w, h);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) out.rgb[i * 3 + size_t(c)] = col[c][i] * dem[c][i];
}

Image atrous_variance(const Film& film) {
    Image var = film.variance_of_mean();
    const int w = film.width(), h = film.height();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (film.pixel(x, y).n >= 2) continue;
            double sum[3] = {}, sum_sq[3] = {};
            int k = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    const FilmPixel& q = film.pixel(xx, yy);
                    if (q.n == 0) continue;
                    for (int c = 0; c < 3; ++c) {
                        const double m = q.mean(c);
                        sum[c] += m;
                        sum_sq[c] += m * m;
                    }
                    ++k;
                }
            if (k < 2) continue;
            for (int c = 0; c < 3; ++c) {
                const double m = sum[c] / k;
                var.rgb[(size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(c)] =
                    static_cast<float>(std::max(0.0, sum_sq[c] / k - m * m));
            }
        }
    return var;
}

Image denoise_atrous(const Image& mean, const Image& variance_of_mean, const FeatureImage& features) {
    AtrousDenoiser d;
    Image out;
    d.denoise(mean, variance_of_mean, features, out);
    return out;
}

}  // namespace pv
