// core/denoise/aov.h: arbitrary output variables (AOVs) beside the RGB mean: first-hit features for denoisers (albedo,
// shading normal, depth) from a separate feature pass, so trace_path and the render loop without AOVs are
// untouched, and the film's per-pixel statistics (sample count, variance of the mean, the even/odd half means);
// plus a multi-layer EXR writer for them.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "core/image/film.h"
#include "core/image/image_io.h"
#include "core/render/integrator.h"
#include "core/scene/camera.h"

// Channel names (pbrt-v4's GBufferFilm where it has one, OpenEXR's "Z" for depth):
//   R G B                        the image (the denoised one with --denoise)
//   Albedo.R Albedo.G Albedo.B   base colour at the first rough hit, tinted by the specular chain before it
//   Ns.X Ns.Y Ns.Z               unit shading normal at that hit, world space, facing the arriving ray
//   Z                            distance travelled from the camera to that hit (through mirrors and glass)
//   SampleCount                  accepted samples of the pixel
//   Variance.R Variance.G Variance.B   variance of the pixel mean (sample variance / n)
//   even.R ... odd.B             means of the even- and odd-indexed samples (independent half estimates)
//   noisy.R noisy.G noisy.B      the undenoised mean (written with --denoise)
// Mirror and glass: the features follow the specular chain to the first rough (non-delta) surface, as denoisers
// expect (glass picks reflection or refraction by its Fresnel weight per feature sample); an emitter ends the
// chain like a rough surface, with its emission clamped to 1 as albedo. Rays that leave the scene give albedo 0, normal
// 0 and Z 0.

namespace pv {

// One first-hit record, and the per-pixel means of them.
struct FeatureSample {
    vec3 albedo{0.f};
    vec3 normal{0.f};
    float depth = 0.f;
};

struct FeatureImage {
    int width = 0, height = 0;
    std::vector<vec3> albedo, normal;  // per pixel, row-major from the top-left
    std::vector<float> depth;
};

// Follows `ray` through delta (mirror, glass) surfaces to the first rough hit; glass picks its branch with the
// sampler's next 1D draw, so a pixel's feature samples average reflection and refraction by their weights.
FeatureSample trace_features(const TraceableScene& ts, Ray ray, Sampler& sampler);

// Features of every pixel averaged over `samples` jittered camera rays (the film's box filter, the lens too).
// Deterministic in (pixel, sample, seed); parallel over rows. When *cancel turns true the remaining rows are
// skipped and the image is incomplete (the caller checks the flag and drops it).
FeatureImage render_features(const TraceableScene& ts, const Camera& camera, int width, int height, int samples = 8,
                             uint32_t seed = 0, const std::atomic<bool>* cancel = nullptr);

// A named group of float channels of one image size: channels[k] is channel k's name; data holds
// channels.size() floats per pixel, interleaved, row-major.
struct ExrLayer {
    std::vector<std::string> channels;
    std::vector<float> data;
};

// The film's statistics as layers: SampleCount, Variance.*, even.*, odd.*.
std::vector<ExrLayer> film_layers(const Film& film);
// The feature image as layers: Albedo.*, Ns.*, Z.
std::vector<ExrLayer> feature_layers(const FeatureImage& features);
// An RGB image as a layer with channel prefix ("" gives R G B, "noisy" gives noisy.R ...).
ExrLayer rgb_layer(const Image& image, const std::string& prefix = "");

// Writes every layer's channels as FLOAT into one EXR (to a temporary name, then renamed); throws pv::Error
// naming the file on failure or when a layer's size does not match width x height.
void write_exr_layers(const std::string& path, int width, int height, const std::vector<ExrLayer>& layers,
                      const Metadata& metadata = {});

// Reads the named FLOAT/HALF channels of an EXR into one layer (channels interleaved); *width and *height get the
// image size. Throws pv::Error naming the file and channel when one is missing.
ExrLayer read_exr_layer(const std::string& path, const std::vector<std::string>& channels, int* width, int* height);

}  // namespace pv
