// shaders/display.frag: shows the linear accumulation. Colour view: exposure (stops), a view transform and the
// display's encoding (the framebuffer is not sRGB, so ImGui's colours stay as they are). Every curve is the twin of
// one in core/image/view_transform.cpp, written in the same float operations in the same order, so that the screen
// and `pathview render -o x.png` agree byte for byte (up to the GPU's rounding; tests/gui checks it). An
// OpenColorIO view is a 3D LUT baked from its processor (core/image/ocio_view.h) behind the same log2 shaper.
// False-colour views map the per-pixel relative error (log scale) or the sample count through the Turbo colour map.
// Compare views (ui/compare.h): A | B split at a divider, B alone (tone-mapped as A), or |A - B| / (B + eps)
// (computed on the CPU) in false colour on the relative error's log scale.
// Textures hold rows from the top of the image down, so the image's top is t = 0.
#version 330 core

in vec2 v_uv;
out vec4 frag_color;

uniform sampler2D u_color;    // RGB32F linear radiance (mean)
uniform sampler2D u_error;    // R32F relative RMS error of the mean
uniform sampler2D u_samples;  // R32F accepted samples
uniform float u_exposure;     // stops
uniform int u_tone_map;       // ViewTransform: 0 clamp, 1 Reinhard, 2 ACES (Narkowicz), 3 AgX, 4 PBR Neutral, 5 OCIO
uniform sampler3D u_lut;      // OpenColorIO: display code values at the shaper's nodes
uniform float u_lut_size;     // nodes per axis
uniform vec2 u_lut_log2;      // log2 of node 1 and of the last node (kLutLog2Min, kLutLog2Max)
uniform int u_view;           // 0 colour, 1 relative error, 2 sample count
uniform float u_samples_max;  // sample count shown as the top of the scale
uniform sampler2D u_b;        // RGB32F linear radiance of the held image B (any size)
uniform sampler2D u_diff;     // R32F |A - B| / (B + eps), averaged over channels
uniform int u_compare;        // 0 A, 1 A | B split, 2 B, 3 difference
uniform float u_divider;      // split: B right of this fraction of the width

// IEC 61966-2-1 sRGB encoding of a linear value in [0, 1] (srgb_encode).
vec3 srgb_from_linear(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

// Narkowicz 2016, "ACES Filmic Tone Mapping Curve": a fit of the ACES RRT + sRGB ODT, input pre-scaled by 0.6.
vec3 aces_fit(vec3 c) {
    vec3 x = c * 0.6;
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// Reinhard et al. 2002, applied to luminance so hues do not shift.
vec3 reinhard(vec3 c) {
    float l = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
    return l > 0.0 ? c * (1.0 / (1.0 + l)) : c;
}

// Khronos PBR Neutral (PBR_Neutral/README.md of KhronosGroup/ToneMapping).
vec3 pbr_neutral(vec3 c) {
    const float kF90 = 0.04;
    const float kStart = 0.8 - kF90;
    const float kDesaturation = 0.15;
    float x = min(c.x, min(c.y, c.z));
    float offset = x <= 2.0 * kF90 ? x - x * x / (4.0 * kF90) : kF90;
    c -= offset;
    float peak = max(c.x, max(c.y, c.z));
    if (peak <= kStart) return c;
    float d = 1.0 - kStart;
    float new_peak = 1.0 - d * d / (peak + d - kStart);
    float g = 1.0 / (kDesaturation * (peak - new_peak) + 1.0);
    return c * (new_peak / peak) * g + vec3(new_peak) * (1.0 - g);
}

// AgX as Blender 4 forms it; the constants and their derivation are in core/image/view_transform.cpp.
const float kAgxLog2Min = -12.4739312;
const float kAgxLog2Range = 16.5;
const float kAgxLogTop = 25.0 / 16.5;
const float kAgxPivotX = 0.606060606;
const float kAgxPivotY = 0.48943709;
const float kAgxSlope = 2.4;
const float kAgxPower = 1.5;
const float kAgxScaleToe = -0.565675607;
const float kAgxScaleShoulder = 0.715198286;
const float kAgxHueRestore = 0.4;

// Row-major matrices, as in C++: out.x = dot(row 0, in).
vec3 agx_inset(vec3 v) {
    return vec3(0.544812996 * v.x + 0.373796137 * v.y + 0.081390866 * v.z,
                0.140415538 * v.x + 0.754143246 * v.y + 0.105441215 * v.z,
                0.088811903 * v.x + 0.178885106 * v.y + 0.732302991 * v.z);
}
vec3 agx_outset(vec3 v) {
    return vec3(1.964894029 * v.x + -0.856007909 * v.y + -0.108886120 * v.z,
                -0.299309079 * v.x + 1.326391892 * v.y + -0.027082813 * v.z,
                -0.164356444 * v.x + -0.238207402 * v.y + 1.402563846 * v.z);
}

vec3 rgb_to_hsv(vec3 c) {
    float hi = max(c.x, max(c.y, c.z));
    float lo = min(c.x, min(c.y, c.z));
    float delta = hi - lo;
    if (delta <= 0.0) return vec3(0.0, 0.0, hi);
    float h;
    if (c.z == hi) h = (4.0 + (c.x - c.y) / delta) / 6.0;
    else if (c.y == hi) h = (2.0 + (c.z - c.x) / delta) / 6.0;
    else h = ((c.y - c.z) / delta) / 6.0;
    if (h < 0.0) h += 1.0;
    return vec3(h, delta / hi, hi);
}

vec3 hsv_to_rgb(vec3 hsv) {
    float h6 = hsv.x * 6.0 >= 6.0 ? 0.0 : hsv.x * 6.0;
    float i = floor(h6), f = h6 - i, s = hsv.y, v = hsv.z;
    float p = v * (1.0 - s), q = v * (1.0 - s * f), t = v * (1.0 - s * (1.0 - f));
    if (i < 1.0) return vec3(v, t, p);
    if (i < 2.0) return vec3(q, v, p);
    if (i < 3.0) return vec3(p, v, t);
    if (i < 4.0) return vec3(p, q, v);
    if (i < 5.0) return vec3(t, p, v);
    return vec3(v, p, q);
}

float agx_log_encode(float v) {
    return clamp((log2(max(v, 1e-10)) - kAgxLog2Min) / kAgxLog2Range, 0.0, kAgxLogTop);
}

float agx_sigmoid(float x) {
    float scale = x < kAgxPivotX ? kAgxScaleToe : kAgxScaleShoulder;
    float t = kAgxSlope * (x - kAgxPivotX) / scale;
    return scale * t / pow(1.0 + pow(t, kAgxPower), 1.0 / kAgxPower) + kAgxPivotY;
}

vec3 agx(vec3 c) {
    vec3 inset = agx_inset(c);
    float hue_before = rgb_to_hsv(inset).x;
    vec3 formed = vec3(agx_sigmoid(agx_log_encode(inset.x)), agx_sigmoid(agx_log_encode(inset.y)),
                       agx_sigmoid(agx_log_encode(inset.z)));
    vec3 hsv = rgb_to_hsv(pow(max(formed, vec3(0.0)), vec3(2.4)));
    hsv.x = hue_before + kAgxHueRestore * (hsv.x - hue_before);
    vec3 o = agx_outset(hsv_to_rgb(hsv));
    float lowest = min(o.x, min(o.y, o.z));
    if (lowest < 0.0) {
        float y = 0.2126 * o.x + 0.7152 * o.y + 0.0722 * o.z;
        o = (o - lowest) * (max(2.0 * y - lowest, 0.0) / max(2.0 * (y - lowest), 1e-30));
    }
    return clamp(pow(max(o, vec3(0.0)), vec3(1.0 / 2.4)), 0.0, 1.0);
}

// The LUT coordinate of a linear value in nodes (lut_coordinate): node 0 is 0, node k >= 1 is
// 2^(log2 min + (k - 1) (log2 max - log2 min) / (size - 2)).
float lut_coordinate(float v) {
    float first = exp2(u_lut_log2.x);
    if (!(v > 0.0)) return 0.0;
    if (v < first) return v / first;
    return min(1.0 + (log2(v) - u_lut_log2.x) / (u_lut_log2.y - u_lut_log2.x) * (u_lut_size - 2.0), u_lut_size - 1.0);
}

vec3 ocio_lut(vec3 c) {
    vec3 u = vec3(lut_coordinate(c.x), lut_coordinate(c.y), lut_coordinate(c.z));
    return texture(u_lut, (u + 0.5) / u_lut_size).rgb;
}

// Turbo (Mikhailov 2019), polynomial approximation; returns display (sRGB-encoded) colour for t in [0, 1].
vec3 turbo(float t) {
    const vec4 kr4 = vec4(0.13572138, 4.61539260, -42.66032258, 132.13108234);
    const vec4 kg4 = vec4(0.09140261, 2.19418839, 4.84296658, -14.18503333);
    const vec4 kb4 = vec4(0.10667330, 12.64194608, -60.58204836, 110.36276771);
    const vec2 kr2 = vec2(-152.94239396, 59.28637943);
    const vec2 kg2 = vec2(4.27729857, 2.82956604);
    const vec2 kb2 = vec2(-89.90310912, 27.34824973);
    t = clamp(t, 0.0, 1.0);
    vec4 v4 = vec4(1.0, t, t * t, t * t * t);
    vec2 v2 = v4.zw * v4.z;
    return vec3(dot(v4, kr4) + dot(v2, kr2), dot(v4, kg4) + dot(v2, kg2), dot(v4, kb4) + dot(v2, kb2));
}

// Exposure, view transform, display encoding (display_encode).
vec4 shade(vec3 radiance) {
    vec3 c = min(max(radiance, 0.0) * exp2(u_exposure), vec3(3.402823e38));
    if (u_tone_map == 3) return vec4(agx(c), 1.0);
    if (u_tone_map == 5) return vec4(ocio_lut(c), 1.0);
    if (u_tone_map == 1) c = reinhard(c);
    else if (u_tone_map == 2) c = aces_fit(c);
    else if (u_tone_map == 4) c = pbr_neutral(c);
    return vec4(srgb_from_linear(c), 1.0);
}

// log10 of a relative error over [1e-3, 1] in Turbo: blue is close, red is far; 0 is black.
vec4 log_error(float e) { return vec4(e > 0.0 ? turbo((log(e) / log(10.0) + 3.0) / 3.0) : vec3(0.0), 1.0); }

void main() {
    vec2 uv = vec2(v_uv.x, 1.0 - v_uv.y);
    // The shading pass covers the snapshot texel for texel (viewport = texture size): fetch, not filter, so a pixel
    // is exactly the film's value.
    ivec2 size = textureSize(u_color, 0);
    ivec2 texel = ivec2(int(gl_FragCoord.x), size.y - 1 - int(gl_FragCoord.y));
    if (u_compare == 3) {
        frag_color = log_error(texture(u_diff, uv).r);
        return;
    }
    if (u_compare == 2 || (u_compare == 1 && v_uv.x >= u_divider)) {
        frag_color = shade(texture(u_b, uv).rgb);
        return;
    }
    if (u_view == 1) {
        // The relative error: blue is converged, red is noisy.
        frag_color = log_error(texelFetch(u_error, texel, 0).r);
        return;
    }
    if (u_view == 2) {
        frag_color = vec4(turbo(texelFetch(u_samples, texel, 0).r / max(u_samples_max, 1.0)), 1.0);
        return;
    }
    frag_color = shade(texelFetch(u_color, texel, 0).rgb);
}
