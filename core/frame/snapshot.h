// core/frame/snapshot.h: what the viewer asks of the progressive driver (RenderRequest) and what it publishes after
// each pass (Snapshot): the accumulation's images, its statistics and its first-frame timings.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/frame/renderer.h"
#include "core/partial/partial.h"

namespace pv {

// What the driver should render. materials: empty = keep the current ones (same count as the scene's);
// environment: nothing = keep the current one.
struct RenderRequest {
    CameraDesc camera;
    RenderSettings settings;
    int width = 1, height = 1;
    std::vector<Material> materials;
    std::optional<EnvironmentSettings> environment;  // nothing = keep the current one
    std::optional<HomogeneousMedium> fog;            // the global medium; nothing = keep the current one
    AdaptiveSettings adaptive;                       // noise threshold (off by default)
    // A render region in this request's pixels (Renderer::set_region; clamped to the image): every sample lands
    // inside it. Nothing: the whole image. Not with adaptive sampling; no resumable snapshot of a region.
    std::optional<PixelRect> region;
};

// The published state of one accumulation after a completed pass. Images are row-major from the top-left.
struct Snapshot {
    uint64_t generation = 0;  // restart() that this accumulation belongs to (0: nothing rendered yet)
    uint64_t serial = 0;      // increases with every publication
    int width = 0, height = 0;
    std::vector<float> rgb;        // mean radiance, 3 floats per pixel
    std::vector<float> rel_error;  // per-pixel relative RMS error of the mean from the half buffers (0 if < 2 spp)
    std::vector<float> samples;    // accepted samples per pixel
    uint32_t spp = 0;
    double seconds = 0.0;  // time spent in completed passes since the restart
    uint64_t rays = 0;     // closest-hit + shadow rays
    uint64_t paths = 0;
    uint64_t dropped = 0;
    double mrays_per_s = 0.0;
    double ms_per_pass = 0.0;     // the last pass
    double rel_mse = 0.0;         // Film::estimated_rel_mse(); 0 below 2 spp
    bool target_reached = false;  // rendering stopped at the target spp / seconds, or every pixel converged
    // Adaptive sampling: the fraction of pixels still taking samples (1 without it), and the estimated seconds of
    // rendering left until every pixel reaches the noise threshold (< 0: unknown), from a log-log fit of the worst
    // active pixel's filtered error against samples over the last checkpoints, at the current pass time.
    std::string sky_guide;                  // Renderer::sky_guide_status()
    std::vector<std::string> light_groups;  // the light groups the film keeps (none: one group), for the live mix
    double active_fraction = 1.0;
    double seconds_to_threshold = -1.0;
    // With set_denoise(true): the a-trous denoised mean (core/denoise/denoise_atrous.h) of this accumulation at
    // denoised_spp samples (it lags spp while rendering: the filter runs at most a third of the time), and the
    // filter's last time. Empty when off or not made yet. rel_mse and every other figure stay the noisy image's.
    std::vector<float> denoised;
    uint32_t denoised_spp = 0;
    double denoise_ms = 0.0;
    // The denoised image is NFOR's (core/denoise/denoise_nfor.h), made once rendering stopped (paused or at its
    // target) with at least ProgressiveRenderer::kNforMinSpp samples; else the a-trous filter's.
    bool denoised_nfor = false;
    // The first publication of an accumulation: the driver's time from taking the request to this snapshot being
    // ready (restart, sky guide, the pass, the denoiser's features and filter, the copy), and the features' share
    // (0 when not denoising). Later snapshots of the same accumulation carry the same figures.
    double first_ready_ms = 0.0;
    double features_ms = 0.0;
    double wait_ms = 0.0;  // from restart() to the driver taking the request (the pass or filter it had to end)
    CameraDesc camera;
    RenderSettings settings;
    PixelRect region;   // the render region (the whole image without one): pixels outside have no samples
    Metadata metadata;  // render_metadata() of this accumulation, for EXR snapshots (with pathview:region)
};

}  // namespace pv
