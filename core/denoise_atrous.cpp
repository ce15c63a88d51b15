// core/denoise_atrous.cpp: edge-avoiding a-trous filtering (see the header).
#include "core/denoise_atrous.h"

#include <algorithm>

namespace pv {
namespace {

constexpr int kPasses = 5;
// B3-spline taps (1/16, 1/4, 3/8, 1/4, 1/16), Dammertz et al. 2010.
constexpr float kTap[5] = {1.f / 16, 1.f / 4, 3.f / 8, 1.f / 4, 1.f / 16};
// Edge-stopping parameters (SVGF, Schied et al. 2017, sec. 4.4; normal exponent 64 below): colour in standard
// deviations, depth relative to the pixel's depth, albedo difference.
constexpr float kSigmaColour = 4.f, kSigmaDepth = 0.02f, kSigmaAlbedo = 0.1f;

}  // namespace

Image denoise_atrous(const Image& mean, const Image& variance_of_mean, const FeatureImage& f) {
    const int w = mean.width, h = mean.height;
    const size_t n = size_t(w) * size_t(h);
    // Demodulate: filter irradiance-like colour / albedo (where albedo is 0, e.g. the sky, the colour itself).
    std::vector<vec3> col(n), tmp(n), alb(n);
    std::vector<float> var(n), tmpv(n);
    for (size_t i = 0; i < n; ++i) {
        alb[i] = glm::max(f.albedo[i], vec3(1e-3f));
        if (f.depth[i] == 0.f) alb[i] = vec3(1.f);
        const vec3 c = mean.at(int(i % size_t(w)), int(i / size_t(w)));
        col[i] = c / alb[i];
        const float a = luminance(alb[i]);
        var[i] = std::max(0.f, (variance_of_mean.rgb[i * 3] + variance_of_mean.rgb[i * 3 + 1] +
                                variance_of_mean.rgb[i * 3 + 2]) /
                                   3.f) /
                 (a * a);
    }
    std::vector<float> sigma(n);  // the colour scale, from the variance box-filtered over 3x3 (SVGF sec. 4.4)
    std::vector<float> lum(n);    // luminance of the current pass's input
    // Unit normals: a pixel across an edge has a shorter mean normal, which would scale every weight it takes.
    std::vector<vec3> nrm(n);
    for (size_t i = 0; i < n; ++i) {
        const float l = glm::length(f.normal[i]);
        nrm[i] = l > 0.f ? f.normal[i] / l : vec3(0.f);
    }
    for (int pass = 0; pass < kPasses; ++pass) {
        const int stride = 1 << pass;
        // A pixel whose few samples all agreed (all zero, say) has variance 0 and would accept no neighbour: a
        // black dot in the output. The neighbourhood's variance is steadier.
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                float acc = 0.f;
                int cnt = 0;
                for (int yy = std::max(0, y - 1); yy <= std::min(h - 1, y + 1); ++yy)
                    for (int xx = std::max(0, x - 1); xx <= std::min(w - 1, x + 1); ++xx, ++cnt)
                        acc += var[size_t(yy) * size_t(w) + size_t(xx)];
                sigma[size_t(y) * size_t(w) + size_t(x)] = kSigmaColour * std::sqrt(acc / float(cnt)) + 1e-4f;
            }
        for (size_t i = 0; i < n; ++i) lum[i] = luminance(col[i]);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t i = size_t(y) * size_t(w) + size_t(x);
                const float li = lum[i];
                const vec3 ni = nrm[i], ai = f.albedo[i];
                const float inv_sigma_l = 1.f / sigma[i];
                const float zi = f.depth[i], dz_scale = kSigmaDepth * std::max(zi, 1e-6f) * float(stride);
                vec3 acc(0.f);
                float acc_v = 0.f, wsum = 0.f;
                for (int ky = 0; ky < 5; ++ky) {
                    const int yy = y + (ky - 2) * stride;
                    if (yy < 0 || yy >= h) continue;
                    for (int kx = 0; kx < 5; ++kx) {
                        const int xx = x + (kx - 2) * stride;
                        if (xx < 0 || xx >= w) continue;
                        const size_t j = size_t(yy) * size_t(w) + size_t(xx);
                        // max(0, n_i . n_j)^64 by six squarings; below 0.85 it is under 3e-5: skip the tap.
                        float wn = glm::dot(ni, nrm[j]);
                        if (!(wn > 0.85f)) continue;
                        for (int k = 0; k < 6; ++k) wn *= wn;
                        const vec3 da = f.albedo[j] - ai;
                        const float e = std::fabs(f.depth[j] - zi) / dz_scale +
                                        glm::dot(da, da) * (1.f / (kSigmaAlbedo * kSigmaAlbedo)) +
                                        std::fabs(lum[j] - li) * inv_sigma_l;
                        if (e > 12.f) continue;  // weight below 6e-6 of the tap's
                        const float wgt = kTap[kx] * kTap[ky] * wn * std::exp(-e);
                        acc += wgt * col[j];
                        acc_v += wgt * wgt * var[j];
                        wsum += wgt;
                    }
                }
                // The centre tap always has weight > 0 (all stopping terms are 1 for j = i unless its normal is 0).
                tmp[i] = wsum > 0.f ? acc / wsum : col[i];
                tmpv[i] = wsum > 0.f ? acc_v / (wsum * wsum) : var[i];
            }
        std::swap(col, tmp);
        std::swap(var, tmpv);
    }
    Image out(w, h);
    for (size_t i = 0; i < n; ++i) out.set(int(i % size_t(w)), int(i / size_t(w)), col[i] * alb[i]);
    return out;
}

}  // namespace pv
