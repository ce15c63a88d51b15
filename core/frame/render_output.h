// core/frame/render_output.h: a rendered film into what is shown or written: the camera's first-hit features, the
// denoised image (NFOR or a-trous), exposure and the EXR layers. `pathview render` writes finish_render()'s output;
// the viewer's stopped accumulation and the benchmark's denoised points go through camera_features and denoise_film.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "core/denoise/aov.h"
#include "core/denoise/denoise_nfor.h"
#include "core/frame/renderer.h"
#include "core/image/image_io.h"

namespace pv {

enum class Denoiser { Nfor, Atrous };

// The features of the renderer's camera and image size that the denoisers use: 8 samples a pixel, with the render's
// seed. When *cancel turns true the image is incomplete (the caller checks the flag and drops it).
FeatureImage camera_features(const Renderer& renderer, const std::atomic<bool>* cancel = nullptr);

// The film's mean denoised: NFOR (final quality, core/denoise/denoise_nfor.h) or the a-trous filter (the viewer's,
// core/denoise/denoise_atrous.h). stats->seconds is the filter's time either way. Cancelled (NFOR only): 0x0.
Image denoise_film(const Film& film, const FeatureImage& features, Denoiser denoiser, NforStats* stats = nullptr,
                   const std::atomic<bool>* cancel = nullptr);

// Beyond this RMS sample value NFOR's window sums of squared colours overflow float (an all-black image at 1e18) and
// the Variance layer holds Inf: 1e16 keeps squares below 1e32, a factor 1e6 from FLT_MAX for the sums.
constexpr double kMaxDenoiseRms = 1e16;
// The largest root-mean-square sample value of any pixel and channel (sqrt(sum_sq / n)).
double largest_rms(const Film& film);

struct OutputOptions {
    bool aovs = false;     // feature and film-statistics layers
    bool denoise = false;  // the denoised image as the main one, the raw mean as the noisy.* layer
    Denoiser denoiser = Denoiser::Nfor;
    float exposure = 0.f;  // stops, applied to the image and the noisy layer
    // Light groups (docs/light-groups.md): the image is the renderer's mix (Renderer::light_gains); with
    // light_groups, each group the film keeps is also a layer LightGroup.<name>.R/G/B (times its gain and the
    // exposure, so the layers add up to the image).
    bool light_groups = false;
};

// "NAME=r,g,b" or "NAME=k" for each of `specs` into gains for the groups `names` (1 for a group not named);
// throws pv::Error naming `what` for a malformed spec, a negative or non-finite gain or a name not in `names`.
LightGains parse_light_gains(const std::vector<std::string>& specs, const std::vector<std::string>& names,
                             const std::string& what);
// A group's name as an EXR layer name: characters other than letters, digits, '_' and '-' become '_'.
std::string light_group_layer_name(const std::string& name);

// What is written: the image (denoised with `denoise`, exposed), its EXR layers (RGB first) and metadata.
struct RenderOutput {
    Image image;
    std::vector<ExrLayer> layers;
    Metadata metadata;
    double aov_seconds = 0.0;
    NforStats nfor;
};

// The renderer's film through the chain: mean, features and denoising (with aovs or denoise), exposure, layers.
// Throws pv::Error for a film too bright for the float statistics (largest_rms above kMaxDenoiseRms) when aovs or
// denoise is asked for.
RenderOutput finish_render(const Renderer& renderer, const OutputOptions& o);

}  // namespace pv
