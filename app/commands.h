// app/commands.h: the pathview subcommands. Each registers its options on the CLI and runs when chosen.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/frame/adaptive.h"
#include "core/image/image_io.h"
#include "core/image/ocio_view.h"
#include "core/image/view_transform.h"
#include "core/render/integrator.h"
#include "core/scene/camera.h"

namespace pv::app {

// Options shared by every subcommand that renders: scene, estimator and camera overrides.
struct CommonOptions {
    std::string scene;  // empty: the built-in Cornell box
    int width = 512, height = 512;
    int threads = 0;  // 0: all cores
    RenderSettings settings;
    AdaptiveSettings adaptive;  // --adaptive (off), --noise-threshold, --min-spp
    std::vector<float> eye, target, up;
    std::optional<float> fov, aperture, focus_distance;
    std::string environment;  // "r,g,b", a number, a map file, or "sky"
    std::optional<float> env_rotation, env_strength;
    std::string bookmark;    // start from this saved camera
    std::vector<float> sun;  // direction toward the sun
    std::optional<float> sun_irradiance, sun_radius;
    std::vector<float> fog;  // --fog SIGMA_S[,SIGMA_A[,G]]: the global medium
    double max_image_megapixels = double(ImageLimits{}.max_pixels) * 1e-6;  // memory budget of one image
    // The flags add_common_options registered that define the image (size, settings, camera, scene overrides):
    // those that `render --resume` takes from the part.
    std::vector<std::string> image_flags;
};

// A CLI11 check: a finite number in [lo, hi] (CLI::Range lets NaN through and accepts inf).
CLI::Validator finite_range(double lo, double hi);
// Refuses, before anything is allocated, a film larger than the memory available (pv::Error with the figure).
void check_film_memory(int width, int height);
// The same for `pathview merge`: the output film of width x height parts (pv::Error naming `part`).
void check_merge_memory(const std::string& part, int width, int height);

// --exposure (stops, applied before writing) and --max-image-megapixels (the budget of one image read), shared by
// render and merge (the budget also by view and bench, through add_common_options) with each one's help.
CLI::Option* add_exposure_option(CLI::App& cmd, float& stops, const std::string& help);
CLI::Option* add_image_budget_option(CLI::App& cmd, double& megapixels, const std::string& help);
// --view-transform and the OpenColorIO flags, shared by view, render and merge (core/image/view_transform.h).
struct DisplayOptions {
    std::string view_transform;  // empty: the command's default (or ocio when an --ocio-* flag is given)
    std::string ocio_config;     // empty: $OCIO
    std::string ocio_display, ocio_view;
    std::string ocio_input = "scene_linear";
};
void add_display_options(CLI::App& cmd, DisplayOptions& o, const char* default_transform);
// The transform the flags ask for (its exposure 0: each command applies its own). An OpenColorIO view is built
// here; throws pv::Error naming the config, or for --ocio-* flags with another transform (but for --ocio-config
// and --ocio-input in the viewer, `offers_config`: the config is then offered in its panel).
DisplayTransform resolve_display(const DisplayOptions& o, ViewTransform fallback, bool offers_config = false);
// The OpenColorIO config the viewer offers in its panel: the chosen view's, --ocio-config, else $OCIO (a broken
// $OCIO is a note on stderr, not an error); null when there is none.
std::shared_ptr<const OcioConfig> offered_ocio_config(const DisplayOptions& o, const DisplayTransform& chosen);

// Adds the shared options to a (sub)command.
void add_common_options(CLI::App& cmd, CommonOptions& o);
// After parsing: caps --threads at the cores this process may use (saying so) and applies the image budget.
// (The on|off and sampler options bind straight to o.settings through CLI11 transformers.)
void resolve_switches(CommonOptions& o);
// Applies --bookmark (a camera saved in the scene file), then the camera flags, to `camera`.
void apply_camera_overrides(const CommonOptions& o, const Scene& scene, CameraDesc& camera);
// Applies --environment / --env-rotation / --env-strength to a loaded scene (throws pv::Error on bad values).
void apply_scene_overrides(const CommonOptions& o, Scene& scene);
// The one scene set-up of render, view and bench, after loading: the scene overrides, its warnings printed (one
// line each), and the camera to render from (the scene's, then --bookmark and the camera flags).
CameraDesc set_up_scene(const CommonOptions& o, Scene& scene);
// The scene path to load (the built-in Cornell box when none was given).
std::string scene_path(const CommonOptions& o);

void add_render_command(CLI::App& app);
void add_view_command(CLI::App& app, CLI::App*& view_cmd);
void add_bench_command(CLI::App& app);
void add_merge_command(CLI::App& app);

}  // namespace pv::app
