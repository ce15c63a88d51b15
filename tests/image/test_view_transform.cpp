// tests/image/test_view_transform.cpp: the view transforms against their published definitions. Each curve is
// recomputed here in double from the published text (the Khronos PBR Neutral specification's equations; AgX from the
// matrices, log range and sigmoid of Blender's LUT generator, EaryChow/AgX_LUT_Gen, and Troy Sobotka's tunable
// sigmoid; Narkowicz's ACES fit; IEC 61966-2-1), independently of the float code and its pre-multiplied constants,
// and the float code must agree within float rounding. Plus the published reference points (PBR Neutral's exact
// reproduction of base colours in [0.08, 0.8]; AgX's middle grey 0.18 -> 0.18^(1/2.4), -10 and +6.5 stops).
// Test kinds: unit
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "core/base/error.h"
#include "core/image/view_transform.h"

namespace pv {
namespace {

using D3 = std::array<double, 3>;
using M3 = std::array<D3, 3>;

D3 mul(const M3& m, const D3& v) {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}
M3 mul(const M3& a, const M3& b) {
    M3 r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
    return r;
}
M3 inverse(const M3& m) {
    const double a = m[0][0], b = m[0][1], c = m[0][2], d = m[1][0], e = m[1][1], f = m[1][2], g = m[2][0], h = m[2][1],
                 i = m[2][2];
    const double A = e * i - f * h, B = f * g - d * i, C = d * h - e * g;
    const double det = a * A + b * B + c * C;
    return {D3{A / det, (c * h - b * i) / det, (b * f - c * e) / det},
            D3{B / det, (a * i - c * g) / det, (c * d - a * f) / det},
            D3{C / det, (b * g - a * h) / det, (a * e - b * d) / det}};
}

// ---- Khronos PBR Neutral, the specification's equations in double.
D3 pbr_neutral_spec(D3 c) {
    const double f90 = 0.04, ks = 0.8 - f90, kd = 0.15;
    const double x = std::min({c[0], c[1], c[2]});
    const double f = x <= 2 * f90 ? x - x * x / (4 * f90) : f90;
    const double p = std::max({c[0] - f, c[1] - f, c[2] - f});
    if (p <= ks) return {c[0] - f, c[1] - f, c[2] - f};
    const double pn = 1 - (1 - ks) * (1 - ks) / (p + 1 - 2 * ks);
    const double g = 1 / (kd * (p - pn) + 1);
    D3 out;
    for (int k = 0; k < 3; ++k) out[k] = (c[k] - f) * pn / p * g + pn * (1 - g);
    return out;
}

TEST(ViewTransform, PbrNeutralReproducesBaseColoursInItsRange) {
    // The specification: c_out = c_in - F90 for every channel in [0.08, 0.8].
    std::mt19937 rng(37);
    std::uniform_real_distribution<float> u(0.08f, 0.8f);
    for (int i = 0; i < 1000; ++i) {
        const vec3 c(u(rng), u(rng), u(rng));
        const vec3 out = pbr_neutral(c);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[k], c[k] - 0.04f, 2e-7f) << c[k];
    }
}

TEST(ViewTransform, PbrNeutralFollowsTheSpecification) {
    std::mt19937 rng(38);
    std::uniform_real_distribution<float> u(-6.f, 8.f);  // log2 of each channel: shadows to far highlights
    for (int i = 0; i < 20000; ++i) {
        const vec3 c(std::exp2(u(rng)), std::exp2(u(rng)), std::exp2(u(rng)));
        const vec3 out = pbr_neutral(c);
        const D3 ref = pbr_neutral_spec({c.x, c.y, c.z});
        for (int k = 0; k < 3; ++k) {
            // Float rounding of a handful of operations on values up to 1 (the compressed branch divides by p,
            // which the test keeps below 2^8).
            EXPECT_NEAR(out[k], ref[k], 2e-6) << c.x << " " << c.y << " " << c.z;
            EXPECT_GE(out[k], 0.f);
            EXPECT_LE(out[k], 1.f);
        }
    }
}

// ---- AgX: Blender's generator in double, from its own matrices (not the pre-multiplied float ones).
const M3 kXyzFromRec2020 = {D3{0.6369535067850740, 0.1446191846692331, 0.1688558539228734},
                            D3{0.2626983389565560, 0.6780087657728165, 0.0592928952706273},
                            D3{0.0000000000000000, 0.0280731358475570, 1.0608272349505707}};
const M3 kRec2020FromXyz = {D3{1.7166634277958805, -0.3556733197301399, -0.2533680878902478},
                            D3{-0.6666738361988869, 1.6164557398246981, 0.0157682970961337},
                            D3{0.0176424817849772, -0.0427769763827532, 0.9422432810184308}};
const M3 kRec709FromXyz = {D3{3.2410032329763587, -1.5373989694887855, -0.4986158819963629},
                           D3{-0.9692242522025164, 1.8759299836951759, 0.0415542263400847},
                           D3{0.0556394198519755, -0.2040112061239099, 1.0571489771875333}};
const M3 kInset = {D3{0.856627153315983, 0.0951212405381588, 0.0482516061458583},
                   D3{0.137318972929847, 0.761241990602591, 0.101439036467562},
                   D3{0.11189821299995, 0.0767994186031903, 0.811302368396859}};
const M3 kOutsetInverse = {D3{0.899796955911611, 0.0871996192028351, 0.013003424885555},
                           D3{0.11142098895748, 0.875575586156966, 0.0130034248855548},
                           D3{0.11142098895748, 0.0871996192028349, 0.801379391839686}};

// Troy Sobotka's tunable sigmoid (after Jed Smith) with AgX's parameters: pivot (10/16.5, 0.18^(1/2.4)), slope 2.4,
// toe and shoulder powers 1.5, limits (0, 0) and (1, 1), no linear section.
double sigmoid_ref(double x) {
    const double px = 10.0 / 16.5, py = std::pow(0.18, 1 / 2.4), s = 2.4, p = 1.5;
    auto scale = [&](double dx, double dy) {
        return std::pow(std::pow(s * dx, -p) * (std::pow(s * dx / dy, p) - 1), -1 / p);
    };
    const double sc = x < px ? -scale(px, py) : scale(1 - px, 1 - py);
    const double t = s * (x - px) / sc;
    return sc * t / std::pow(1 + std::pow(t, p), 1 / p) + py;
}

D3 hsv_of(D3 c) {
    const double hi = std::max({c[0], c[1], c[2]}), lo = std::min({c[0], c[1], c[2]}), d = hi - lo;
    if (d <= 0) return {0, 0, hi};
    double h = c[2] == hi ? 4 + (c[0] - c[1]) / d : c[1] == hi ? 2 + (c[2] - c[0]) / d : (c[1] - c[2]) / d;
    h /= 6;
    if (h < 0) h += 1;
    return {h, d / hi, hi};
}
D3 rgb_of(D3 hsv) {
    const double h6 = hsv[0] * 6 >= 6 ? 0 : hsv[0] * 6, i = std::floor(h6), f = h6 - i, s = hsv[1], v = hsv[2];
    const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    switch (int(i)) {
        case 0:
            return {v, t, p};
        case 1:
            return {q, v, p};
        case 2:
            return {p, v, t};
        case 3:
            return {p, q, v};
        case 4:
            return {t, p, v};
        default:
            return {v, p, q};
    }
}

D3 agx_ref(D3 c) {
    const M3 rec2020_from_709 = mul(kRec2020FromXyz, inverse(kRec709FromXyz));
    const D3 inset = mul(kInset, mul(rec2020_from_709, c));
    const double hue_before = hsv_of(inset)[0];
    D3 formed;
    for (int k = 0; k < 3; ++k) {
        const double e = std::clamp((std::log2(std::max(inset[k], 1e-10) / 0.18) + 10) / 16.5, 0.0, 25 / 16.5);
        formed[k] = std::pow(std::max(sigmoid_ref(e), 0.0), 2.4);
    }
    D3 hsv = hsv_of(formed);
    hsv[0] = hue_before + 0.4 * (hsv[0] - hue_before);
    D3 out = mul(mul(kRec709FromXyz, kXyzFromRec2020), mul(inverse(kOutsetInverse), rgb_of(hsv)));
    const double lowest = std::min({out[0], out[1], out[2]});
    if (lowest < 0) {
        const double y = 0.2126 * out[0] + 0.7152 * out[1] + 0.0722 * out[2];
        for (double& v : out) v = (v - lowest) * std::max(2 * y - lowest, 0.0) / std::max(2 * (y - lowest), 1e-30);
    }
    for (double& v : out) v = std::min(std::pow(std::max(v, 0.0), 1 / 2.4), 1.0);
    return out;
}

TEST(ViewTransform, AgxSigmoidPassesThroughItsPivotAndLimits) {
    EXPECT_NEAR(agx_sigmoid(0.f), 0.f, 1e-6f);
    EXPECT_NEAR(agx_sigmoid(1.f), 1.f, 1e-6f);
    EXPECT_NEAR(agx_sigmoid(10.f / 16.5f), std::pow(0.18, 1 / 2.4), 1e-7);
    // The slope at the pivot is 2.4 (central difference; the curve is smooth there, h^2 error ~1e-6).
    const float h = 1e-3f, px = 10.f / 16.5f;
    EXPECT_NEAR((agx_sigmoid(px + h) - agx_sigmoid(px - h)) / (2 * h), 2.4, 2e-3);
    for (float x = 0.f; x <= 1.5f; x += 1.f / 256) {
        EXPECT_NEAR(agx_sigmoid(x), sigmoid_ref(x), 1e-6) << x;
        EXPECT_LT(agx_sigmoid(x), agx_sigmoid(x + 1.f / 256)) << x;  // increasing
    }
}

TEST(ViewTransform, AgxMapsGreysThroughItsSigmoid) {
    // A grey stays grey through every matrix (rows sum to 1), so its code value is sigmoid(log encoding).
    EXPECT_NEAR(agx(vec3(0.18f)).x, std::pow(0.18, 1 / 2.4), 2e-6);  // middle grey: 0.48944, byte 125
    EXPECT_EQ(display_byte(agx(vec3(0.18f)).x), 125);
    EXPECT_NEAR(agx(vec3(0.18f * std::exp2(6.5f))).x, 1.0, 2e-6);   // +6.5 stops: white
    EXPECT_NEAR(agx(vec3(0.18f * std::exp2(-10.f))).x, 0.0, 1e-5);  // -10 stops: black
    EXPECT_EQ(agx(vec3(0.f)), vec3(0.f));
    for (float stops = -10.f; stops <= 6.5f; stops += 0.25f) {
        const vec3 out = agx(vec3(0.18f * std::exp2(stops)));
        EXPECT_NEAR(out.x, sigmoid_ref((stops + 10) / 16.5), 3e-6) << stops;
        EXPECT_NEAR(out.y, out.x, 2e-6f);
        EXPECT_NEAR(out.z, out.x, 2e-6f);
    }
}

TEST(ViewTransform, AgxFollowsBlendersGenerator) {
    std::mt19937 rng(39);
    std::uniform_real_distribution<float> u(-14.f, 9.f);
    std::uniform_int_distribution<int> zero(0, 5);  // some channels exactly 0: saturated primaries and secondaries
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
        vec3 c(std::exp2(u(rng)), std::exp2(u(rng)), std::exp2(u(rng)));
        for (int k = 0; k < 3; ++k)
            if (zero(rng) == 0) c[k] = 0.f;
        const vec3 out = agx(c);
        const D3 ref = agx_ref({c.x, c.y, c.z});
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(out[k] - ref[k]));
    }
    // The float chain (pre-multiplied matrices, float log2 and pow) against double: well under a code value
    // (1/255 = 3.9e-3) wherever the hue is not at HSV's wrap (h = 0 = 1, a discontinuity of the generator's lerp).
    EXPECT_LT(worst, 2e-4);
}

TEST(ViewTransform, SrgbAcesAndReinhardFollowTheirDefinitions) {
    EXPECT_NEAR(srgb_encode(0.18f), 0.46135613, 1e-6);  // IEC 61966-2-1: 1.055 * 0.18^(1/2.4) - 0.055
    EXPECT_NEAR(srgb_encode(0.5f), 0.73535698, 1e-6);
    EXPECT_NEAR(srgb_encode(0.002f), 0.02584, 1e-6);  // the linear segment, 12.92 x
    EXPECT_NEAR(srgb_encode(2.f), 1.f, 1e-7f);
    EXPECT_EQ(srgb_encode(-1.f), 0.f);
    for (float x : {0.01f, 0.18f, 1.f, 4.f, 100.f}) {
        const double a = 0.6 * x, ref = std::min(1.0, (a * (2.51 * a + 0.03)) / (a * (2.43 * a + 0.59) + 0.14));
        EXPECT_NEAR(aces_fit(vec3(x)).x, ref, 1e-6) << x;
    }
    const vec3 c(2.f, 1.f, 0.5f);
    const double l = 0.2126 * 2 + 0.7152 * 1 + 0.0722 * 0.5;
    EXPECT_NEAR(reinhard(c).x, 2 / (1 + l), 1e-6);
    EXPECT_NEAR(reinhard(c).z, 0.5 / (1 + l), 1e-6);
}

TEST(ViewTransform, DisplayBytesApplyExposureAndRoundToNearest) {
    Image img(3, 1);
    img.set(0, 0, vec3(0.18f, 0.5f, 1.f));
    img.set(1, 0, vec3(-1.f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()));
    img.set(2, 0, vec3(0.09f, 0.25f, 0.5f));
    DisplayTransform t;
    t.exposure = 1.f;  // x2: the third pixel becomes the first
    const std::vector<uint8_t> b = display_bytes(img, t);
    ASSERT_EQ(b.size(), 9u);
    EXPECT_EQ(b[6], display_byte(srgb_encode(0.18f)));
    EXPECT_EQ(b[6], 118);  // 0.46136 * 255 = 117.6
    EXPECT_EQ(b[8], 255);
    EXPECT_EQ(b[3], 0);    // negative: black
    EXPECT_EQ(b[4], 255);  // an overflow: the brightest value
    EXPECT_EQ(display_byte(0.5f / 255.f), 1);
    EXPECT_EQ(display_byte(0.49f / 255.f), 0);
    EXPECT_EQ(display_byte(std::numeric_limits<float>::quiet_NaN()), 0);
    t.transform = ViewTransform::Agx;
    t.exposure = 0.f;
    img.set(0, 0, vec3(0.18f));
    EXPECT_EQ(display_bytes(img, t)[0], 125);  // AgX's middle grey
    t.transform = ViewTransform::Ocio;         // without a processor
    EXPECT_THROW(display_bytes(img, t), Error);
}

}  // namespace
}  // namespace pv
