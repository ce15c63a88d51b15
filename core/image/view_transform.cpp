// core/image/view_transform.cpp: the built-in view transforms (see view_transform.h). Every curve is written in
// float, in the order of its twin in shaders/display.frag, so that the viewer's bytes and a PNG's agree.
#include "core/image/view_transform.h"

#include <cfloat>
#include <cmath>

#include "core/base/error.h"
#include "core/base/parallel.h"
#include "core/image/ocio_view.h"

namespace pv {
namespace {

// AgX as Blender 4 forms it (EaryChow's AgX_LUT_Gen, AgXBaseRec2020.py and AgXBasesRGB.py, after Troy Sobotka's
// SB2383 AgX): in Rec.2020, an inset matrix, a log2 encoding from -10 to +6.5 stops around middle grey 0.18, the
// sigmoid, a 2.4 power back to linear, 40% of the hue the sigmoid moved restored, the outset matrix, back to Rec.709
// and the display encoding, a 2.4 power. kAgxIn = inset x (Rec.709 -> Rec.2020); kAgxOut = (Rec.2020 -> Rec.709) x
// outset (the outset is the inverse of the SB2383 matrix for rotate 0, inset [0.4, 0.22, 0.04]); both from the
// generator's matrices in double, rows summing to 1 (a grey stays grey). Rows: out.x = dot(row 0, in).
constexpr float kAgxIn[3][3] = {{0.544812996f, 0.373796137f, 0.081390866f},
                                {0.140415538f, 0.754143246f, 0.105441215f},
                                {0.088811903f, 0.178885106f, 0.732302991f}};
constexpr float kAgxOut[3][3] = {{1.964894029f, -0.856007909f, -0.108886120f},
                                 {-0.299309079f, 1.326391892f, -0.027082813f},
                                 {-0.164356444f, -0.238207402f, 1.402563846f}};
constexpr float kAgxLog2Min = -12.4739312f;  // log2(0.18) - 10: normalised 0
constexpr float kAgxLog2Range = 16.5f;       // stops from normalised 0 to 1 (+6.5 stops over middle grey)
constexpr float kAgxLogTop = 25.f / 16.5f;   // +15 stops, where Blender's LUT domain ends
// The sigmoid's pivot (middle grey: x 10/16.5, y 0.18^(1/2.4)), slope there, toe and shoulder powers (1.5, 1.5) and
// the scales that make it pass through (0, 0) and (1, 1): scale = [(s d)^-p ((s d / h)^p - 1)]^(-1/p) with d and h
// the pivot's distances to that limit in x and y (tests/image/test_view_transform.cpp recomputes them in double).
constexpr float kAgxPivotX = 0.606060606f;
constexpr float kAgxPivotY = 0.48943709f;
constexpr float kAgxSlope = 2.4f;
constexpr float kAgxPower = 1.5f;
constexpr float kAgxScaleToe = -0.565675607f;
constexpr float kAgxScaleShoulder = 0.715198286f;
constexpr float kAgxHueRestore = 0.4f;  // the generator's mix_percent: 40% of the sigmoid's hue shift is kept

vec3 mat_mul(const float (&m)[3][3], vec3 v) {
    return vec3(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z);
}

// Hue, saturation and value (hue in [0, 1), 0 for a grey), as the colour-science package computes them.
vec3 rgb_to_hsv(vec3 c) {
    const float hi = max_component(c);
    const float lo = glm::min(c.x, glm::min(c.y, c.z));
    const float delta = hi - lo;
    if (delta <= 0.f) return vec3(0.f, 0.f, hi);
    float h;
    if (c.z == hi)
        h = (4.f + (c.x - c.y) / delta) / 6.f;
    else if (c.y == hi)
        h = (2.f + (c.z - c.x) / delta) / 6.f;
    else
        h = ((c.y - c.z) / delta) / 6.f;
    if (h < 0.f) h += 1.f;
    return vec3(h, delta / hi, hi);
}

vec3 hsv_to_rgb(vec3 hsv) {
    const float h6 = hsv.x * 6.f >= 6.f ? 0.f : hsv.x * 6.f;
    const float i = std::floor(h6), f = h6 - i, s = hsv.y, v = hsv.z;
    const float p = v * (1.f - s), q = v * (1.f - s * f), t = v * (1.f - s * (1.f - f));
    if (i < 1.f) return vec3(v, t, p);
    if (i < 2.f) return vec3(q, v, p);
    if (i < 3.f) return vec3(p, v, t);
    if (i < 4.f) return vec3(p, q, v);
    if (i < 5.f) return vec3(t, p, v);
    return vec3(v, p, q);
}

float agx_log_encode(float v) {
    return glm::clamp((std::log2(glm::max(v, 1e-10f)) - kAgxLog2Min) / kAgxLog2Range, 0.f, kAgxLogTop);
}

}  // namespace

std::string view_transform_choices() {
    std::string s;
    for (const NamedValue<ViewTransform>& e : kViewTransformNames) s += (s.empty() ? "" : "|") + std::string(e.name);
    return s;
}

float srgb_encode(float x) {
    x = glm::clamp(x, 0.f, 1.f);
    return x < 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.f / 2.4f) - 0.055f;
}

vec3 reinhard(vec3 c) {
    const float l = 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
    return l > 0.f ? c * (1.f / (1.f + l)) : c;
}

vec3 aces_fit(vec3 c) {
    const vec3 x = c * 0.6f;
    return glm::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.f, 1.f);
}

vec3 pbr_neutral(vec3 c) {
    constexpr float kF90 = 0.04f;           // Fresnel at normal incidence for IOR 1.5
    constexpr float kStart = 0.8f - kF90;   // K_s: where highlight compression starts
    constexpr float kDesaturation = 0.15f;  // K_d
    const float x = glm::min(c.x, glm::min(c.y, c.z));
    const float offset = x <= 2.f * kF90 ? x - x * x / (4.f * kF90) : kF90;
    c -= offset;
    const float peak = max_component(c);
    if (peak <= kStart) return c;
    const float d = 1.f - kStart;
    const float new_peak = 1.f - d * d / (peak + d - kStart);
    const float g = 1.f / (kDesaturation * (peak - new_peak) + 1.f);
    return c * (new_peak / peak) * g + vec3(new_peak) * (1.f - g);
}

float agx_sigmoid(float x) {
    const float scale = x < kAgxPivotX ? kAgxScaleToe : kAgxScaleShoulder;
    const float t = kAgxSlope * (x - kAgxPivotX) / scale;  // >= 0 on both sides
    return scale * t / std::pow(1.f + std::pow(t, kAgxPower), 1.f / kAgxPower) + kAgxPivotY;
}

vec3 agx(vec3 c) {
    const vec3 inset = mat_mul(kAgxIn, c);
    const float hue_before = rgb_to_hsv(inset).x;
    const vec3 formed(agx_sigmoid(agx_log_encode(inset.x)), agx_sigmoid(agx_log_encode(inset.y)),
                      agx_sigmoid(agx_log_encode(inset.z)));
    vec3 hsv = rgb_to_hsv(glm::pow(glm::max(formed, vec3(0.f)), vec3(2.4f)));
    hsv.x = hue_before + kAgxHueRestore * (hsv.x - hue_before);
    vec3 out = mat_mul(kAgxOut, hsv_to_rgb(hsv));
    // The low guard rail of the generator (after Sakari Kapanen): a colour outside Rec.709 is offset until its
    // smallest channel is 0 and scaled back toward the luminance it had, (2Y - min) / (2Y' - min') in its terms
    // (Rec.709 weights here; the generator's sRGB rail uses Rec.2020 CIE 2015 weights, a few thousandths apart).
    const float lowest = glm::min(out.x, glm::min(out.y, out.z));
    if (lowest < 0.f) {
        const float y = 0.2126f * out.x + 0.7152f * out.y + 0.0722f * out.z;
        out = (out - lowest) * (glm::max(2.f * y - lowest, 0.f) / glm::max(2.f * (y - lowest), 1e-30f));
    }
    return glm::clamp(glm::pow(glm::max(out, vec3(0.f)), vec3(1.f / 2.4f)), 0.f, 1.f);
}

vec3 display_encode(ViewTransform transform, vec3 c) {
    switch (transform) {
        case ViewTransform::Reinhard:
            c = reinhard(c);
            break;
        case ViewTransform::Aces:
            c = aces_fit(c);
            break;
        case ViewTransform::Agx:
            return agx(c);
        case ViewTransform::PbrNeutral:
            c = pbr_neutral(c);
            break;
        default:
            break;
    }
    return vec3(srgb_encode(c.x), srgb_encode(c.y), srgb_encode(c.z));
}

std::string DisplayTransform::describe() const {
    std::string s =
        transform == ViewTransform::Ocio && ocio ? "ocio " + ocio->describe() : name_of(kViewTransformNames, transform);
    if (exposure != 0.f) {
        char buf[48];
        std::snprintf(buf, sizeof buf, ", exposure %+g", double(exposure));
        s += buf;
    }
    return s;
}

std::vector<uint8_t> display_bytes(const Image& image, const DisplayTransform& t) {
    if (t.transform == ViewTransform::Ocio && !t.ocio)
        throw Error("view transform ocio: no OpenColorIO config (give --ocio-config FILE or set $OCIO)");
    const size_t pixels = size_t(image.width) * size_t(image.height);
    std::vector<uint8_t> out(pixels * 3);
    const float scale = std::exp2(t.exposure);
    constexpr int kRows = 16;  // rows a task
    parallel_for_range(0, (image.height + kRows - 1) / kRows, [&](const tbb::blocked_range<int>& r) {
        std::vector<float> row;
        for (int block = r.begin(); block < r.end(); ++block) {
            const size_t begin = size_t(block) * kRows * size_t(image.width);
            const size_t end = std::min(pixels, begin + kRows * size_t(image.width));
            row.resize((end - begin) * 3);
            for (size_t i = 0; i < row.size(); ++i) {
                // As the shader: negative radiance (and NaN) is black, an overflow the largest float.
                const float x = image.rgb[begin * 3 + i];
                const float v = x > 0.f ? x * scale : 0.f;
                row[i] = v <= FLT_MAX ? v : FLT_MAX;
            }
            if (t.transform == ViewTransform::Ocio) t.ocio->apply(row.data(), end - begin);
            for (size_t p = 0; p < end - begin; ++p) {
                vec3 c(row[p * 3], row[p * 3 + 1], row[p * 3 + 2]);
                if (t.transform != ViewTransform::Ocio) c = display_encode(t.transform, c);
                for (int k = 0; k < 3; ++k) out[(begin + p) * 3 + k] = display_byte(c[k]);
            }
        }
    });
    return out;
}

}  // namespace pv
