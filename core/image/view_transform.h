// core/image/view_transform.h: the view transforms that turn linear radiance (Rec.709 primaries, the film's RGB)
// into display code values: clamp, Reinhard, ACES (Narkowicz's fit), AgX (Blender 4's) and Khronos PBR Neutral,
// each ending in the display's encoding (sRGB, or AgX's own 2.4 power), plus an OpenColorIO display/view
// (core/image/ocio_view.h). A view transform is display only: EXR files and the film stay linear.
// shaders/display.frag holds the GLSL twin of every curve here, line for line; the viewer checks that both give
// the same bytes (tests/gui) and tests/image/test_view_transform.cpp checks these against published values.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/base/math.h"
#include "core/base/text.h"
#include "core/image/film.h"

namespace pv {

class OcioView;

// The display shader's u_tone_map takes these values.
enum class ViewTransform : int { Clamp = 0, Reinhard = 1, Aces = 2, Agx = 3, PbrNeutral = 4, Ocio = 5 };
inline constexpr NamedValue<ViewTransform> kViewTransformNames[] = {
    {"clamp", ViewTransform::Clamp}, {"reinhard", ViewTransform::Reinhard},      {"aces", ViewTransform::Aces},
    {"agx", ViewTransform::Agx},     {"pbr-neutral", ViewTransform::PbrNeutral}, {"ocio", ViewTransform::Ocio},
};
// "clamp|reinhard|aces|agx|pbr-neutral|ocio", for help texts and messages.
std::string view_transform_choices();

// IEC 61966-2-1 sRGB encoding of a linear value (clamped to [0, 1] first).
float srgb_encode(float linear);
// Reinhard et al. 2002 on luminance (no hue shift): c / (1 + L). Linear in, linear out.
vec3 reinhard(vec3 c);
// Narkowicz 2016, "ACES Filmic Tone Mapping Curve": a fit of the ACES RRT + sRGB ODT, input pre-scaled by 0.6.
vec3 aces_fit(vec3 c);
// Khronos PBR Neutral (KhronosGroup/ToneMapping, PBR_Neutral/README.md): linear in, linear in [0, 1] out.
vec3 pbr_neutral(vec3 c);
// AgX's sigmoid (Jed Smith's tunable sigmoid with Troy Sobotka's AgX parameters): normalised log2 exposure in,
// 2.4-power encoded value out; passes through (0, 0), (10/16.5, 0.18^(1/2.4)) with slope 2.4, and (1, 1).
float agx_sigmoid(float x);
// AgX base as Blender 4 forms it, for an sRGB display: linear Rec.709 in, display code values in [0, 1] out.
vec3 agx(vec3 c);

// A built-in view transform (not Ocio) of exposed linear radiance `c`, as display code values in [0, 1].
vec3 display_encode(ViewTransform transform, vec3 c);
// A code value in [0, 1] as a byte, rounded to nearest as GL's conversion to an 8-bit target (NaN: 0).
inline uint8_t display_byte(float v) {
    const float x = v * 255.f + 0.5f;
    return x >= 255.f ? 255 : x > 0.f ? static_cast<uint8_t>(x) : 0;
}

// Everything that turns the film's linear image into display bytes: the exposure and the view transform.
struct DisplayTransform {
    float exposure = 0.f;  // stops, multiplied in before the transform
    ViewTransform transform = ViewTransform::Clamp;
    std::shared_ptr<const OcioView> ocio;  // with ViewTransform::Ocio
    // "agx", "ocio sRGB/Standard" ..., with the exposure when not 0: for logs and metadata.
    std::string describe() const;
};

// The image as 8-bit RGB display code values, row 0 at the top (the bytes a PNG of it holds). Negative and NaN
// radiance is black, +inf (or an exposure's overflow) the largest float. Throws pv::Error for Ocio without a processor.
std::vector<uint8_t> display_bytes(const Image& image, const DisplayTransform& transform);

}  // namespace pv
