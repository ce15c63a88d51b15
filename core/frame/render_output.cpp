// core/frame/render_output.cpp: see render_output.h.
#include "core/frame/render_output.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/base/error.h"
#include "core/denoise/denoise_atrous.h"

namespace pv {

FeatureImage camera_features(const Renderer& renderer, const std::atomic<bool>* cancel) {
    const Film& film = renderer.film();
    return render_features(renderer.traceable(), renderer.camera(), film.width(), film.height(), 8,
                           renderer.settings().seed, cancel);
}

Image denoise_film(const Film& film, const FeatureImage& features, Denoiser denoiser, NforStats* stats,
                   const std::atomic<bool>* cancel) {
    if (denoiser == Denoiser::Nfor) return denoise_nfor(film, features, stats, cancel);
    const auto t0 = std::chrono::steady_clock::now();
    Image out = denoise_atrous(film.mean(), atrous_variance(film), features);
    if (stats) stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

double largest_rms(const Film& film) {
    double largest = 0.0;
    for (const FilmPixel& px : film.pixels())
        if (px.n)
            for (int c = 0; c < 3; ++c) largest = std::max(largest, px.sum_sq[c] / px.n);
    return std::sqrt(largest);
}

namespace {

// With aovs or denoise: the first-hit feature pass after the render (the render loop itself is unchanged), the
// denoised image and the feature layers. Refuses a film too bright for the float statistics.
void add_features(const OutputOptions& o, const Renderer& renderer, RenderOutput& out, Image& noisy) {
    const double rms = largest_rms(renderer.film());
    if (rms > kMaxDenoiseRms) {
        char msg[400];
        std::snprintf(msg, sizeof msg,
                      "%s: the brightest pixel's RMS radiance is %.3g, beyond the %.0e that the Variance layer and "
                      "the denoisers compute in float; scale the emission, --env-strength or --sun-irradiance down "
                      "(without %s the render is written as is)",
                      o.denoise ? "--denoise" : "--aovs", rms, kMaxDenoiseRms, o.denoise ? "--denoise" : "--aovs");
        throw Error(msg);
    }
    const auto aov_start = std::chrono::steady_clock::now();
    const FeatureImage features = camera_features(renderer);
    out.aov_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - aov_start).count();
    if (o.denoise) {
        noisy = out.image;
        out.image = denoise_film(renderer.film(), features, o.denoiser, &out.nfor);
        out.metadata["pathview:denoiser"] = o.denoiser == Denoiser::Nfor ? "nfor" : "atrous";
        out.metadata["pathview:denoise_seconds"] = std::to_string(out.nfor.seconds);
    }
    if (o.aovs)
        for (ExrLayer& l : feature_layers(features)) out.layers.push_back(std::move(l));
}

}  // namespace

RenderOutput finish_render(const Renderer& renderer, const OutputOptions& o) {
    RenderOutput out;
    out.image = renderer.film().mean();
    out.metadata = render_metadata(renderer);
    Image noisy;
    if (o.aovs || o.denoise) add_features(o, renderer, out, noisy);
    if (o.exposure != 0.f)
        for (Image* im : {&out.image, &noisy})
            for (float& v : im->rgb) {
                // Overflow saturates: a file never holds Inf (the film's means are finite and non-negative).
                const float s = v * std::exp2(o.exposure);
                v = std::isfinite(s) ? s : std::numeric_limits<float>::max();
            }
    out.layers.insert(out.layers.begin(), rgb_layer(out.image));
    if (o.denoise) out.layers.push_back(rgb_layer(noisy, "noisy"));
    if (o.aovs)
        for (ExrLayer& l : film_layers(renderer.film())) out.layers.push_back(std::move(l));
    return out;
}

}  // namespace pv
