// shaders/display.frag: shows the linear accumulation. Colour view: exposure (stops), a tone map, then the sRGB
// transfer function (the framebuffer is not sRGB, so ImGui's colours stay as they are). False-colour views map
// the per-pixel relative error (log scale) or the sample count through the Turbo colour map.
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
uniform int u_tone_map;       // 0 clamp, 1 Reinhard on luminance, 2 ACES filmic (Narkowicz fit)
uniform int u_view;           // 0 colour, 1 relative error, 2 sample count
uniform float u_samples_max;  // sample count shown as the top of the scale
uniform sampler2D u_b;        // RGB32F linear radiance of the held image B (any size)
uniform sampler2D u_diff;     // R32F |A - B| / (B + eps), averaged over channels
uniform int u_compare;        // 0 A, 1 A | B split, 2 B, 3 difference
uniform float u_divider;      // split: B right of this fraction of the width

// IEC 61966-2-1 sRGB transfer of a linear value in [0, 1].
vec3 srgb_from_linear(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

// Krzysztof Narkowicz, "ACES Filmic Tone Mapping Curve" (2016): a fit of the ACES RRT+ODT, input pre-scaled by 0.6.
vec3 aces_fit(vec3 x) {
    x *= 0.6;
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// Reinhard et al. 2002, applied to luminance so hues do not shift.
vec3 reinhard(vec3 c) {
    float l = dot(c, vec3(0.2126, 0.7152, 0.0722));
    return l > 0.0 ? c * (1.0 / (1.0 + l)) : c;
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

// Exposure, tone map, sRGB.
vec4 shade(vec3 radiance) {
    vec3 c = max(radiance, 0.0) * exp2(u_exposure);
    if (u_tone_map == 1) c = reinhard(c);
    else if (u_tone_map == 2) c = aces_fit(c);
    return vec4(srgb_from_linear(c), 1.0);
}

// log10 of a relative error over [1e-3, 1] in Turbo: blue is close, red is far; 0 is black.
vec4 log_error(float e) { return vec4(e > 0.0 ? turbo((log(e) / log(10.0) + 3.0) / 3.0) : vec3(0.0), 1.0); }

void main() {
    vec2 uv = vec2(v_uv.x, 1.0 - v_uv.y);
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
        frag_color = log_error(texture(u_error, uv).r);
        return;
    }
    if (u_view == 2) {
        frag_color = vec4(turbo(texture(u_samples, uv).r / max(u_samples_max, 1.0)), 1.0);
        return;
    }
    frag_color = shade(texture(u_color, uv).rgb);
}
