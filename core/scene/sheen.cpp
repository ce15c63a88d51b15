// core/scene/sheen.cpp: the Charlie sheen lobe and its albedo table (core/scene/sheen.h).
#include "core/scene/sheen.h"

#include <algorithm>
#include <cmath>

#include "core/scene/sheen_table.h"

namespace pv {
using sheen_detail::kSheenAlbedo;

float sheen_d(float cos_h, float alpha) {
    const float inv = 1.f / std::max(alpha, kSheenMinAlpha);
    const float sin2 = std::max(0.f, 1.f - cos_h * cos_h);
    return (2.f + inv) * std::pow(sin2, 0.5f * inv) * (0.5f * kInvPi);
}

float sheen_lambda(float cos_t, float alpha) {
    // the paper's fit, its coefficients interpolated by (1 - r)^2 between r = 0 and r = 1
    const float r = std::clamp(alpha, kSheenMinAlpha, 1.f);
    const float t = (1.f - r) * (1.f - r);
    const float a = t * 25.3245f + (1.f - t) * 21.5473f;
    const float b = t * 3.32435f + (1.f - t) * 3.82987f;
    const float c = t * 0.16801f + (1.f - t) * 0.19823f;
    const float d = t * -1.27393f + (1.f - t) * -1.97760f;
    const float e = t * -4.85967f + (1.f - t) * -4.32054f;
    const auto L = [&](float x) { return a / (1.f + b * std::pow(x, c)) + d * x + e; };
    const float ct = std::clamp(cos_t, 0.f, 1.f);
    return ct < 0.5f ? std::exp(L(ct)) : std::exp(2.f * L(0.5f) - L(1.f - ct));
}

float sheen_eval(vec3 wo, vec3 wi, float alpha) {
    if (!(wo.z * wi.z > 0.f)) return 0.f;
    const float co = std::abs(wo.z), ci = std::abs(wi.z);
    vec3 h = wo + wi;
    const float len = glm::length(h);
    if (!(len > 0.f)) return 0.f;
    const float cos_h = std::abs(h.z) / len;
    const float g = 1.f / (1.f + sheen_lambda(co, alpha) + sheen_lambda(ci, alpha));
    return sheen_d(cos_h, alpha) * g / (4.f * co * ci);
}

float sheen_albedo(float mu, float alpha) {
    constexpr int n = 16;
    if (!(mu >= 0.f)) mu = 0.f;  // NaN too: the int conversions below must see a finite value
    if (!(alpha >= 0.f)) alpha = 0.f;
    const float x = std::clamp(mu, 0.f, 1.f) * float(n - 1), y = std::clamp(alpha, 0.f, 1.f) * float(n - 1);
    const int i = std::min(int(x), n - 2), j = std::min(int(y), n - 2);
    const float fx = x - float(i), fy = y - float(j);
    const float lo = kSheenAlbedo[i][j] * (1.f - fy) + kSheenAlbedo[i][j + 1] * fy;
    const float hi = kSheenAlbedo[i + 1][j] * (1.f - fy) + kSheenAlbedo[i + 1][j + 1] * fy;
    return std::clamp(lo * (1.f - fx) + hi * fx, 0.f,
                      1.f);  // the mu = 0 row at small alpha exceeds 1 (the grid does not resolve the grazing spike)
}

}  // namespace pv
