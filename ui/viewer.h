// ui/viewer.h: the interactive viewer's entry point (`pathview view`). One GLFW window with an OpenGL 3.3 core
// context: the image region on the left shows the progressive accumulation, the ImGui panel sits on the right.
// Rendering runs on the ProgressiveRenderer's threads; the UI thread only posts restarts and copies snapshots.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "core/frame/progressive.h"
#include "core/image/ocio_view.h"
#include "core/image/view_transform.h"

namespace pv::ui {

struct ViewerOptions {
    // Loads the scene with any camera overrides applied (throws pv::Error); called once a display is open.
    std::function<Scene()> load_scene;
    RenderSettings settings;
    AdaptiveSettings adaptive;      // --noise-threshold, --min-spp
    int width = 512, height = 512;  // the initial image region, in pixels
    int threads = 0;                // 0: all cores
    std::string snapshot_dir = ".";
    std::string log_file;  // empty: no log
    // The display at the start: exposure and view transform (--exposure, --view-transform, --ocio-*).
    DisplayTransform display{0.f, ViewTransform::Aces, nullptr};
    std::shared_ptr<const OcioConfig> ocio_config;  // offered in the Display section (null: none)
    std::string ocio_input = "scene_linear";
    // --compare FILE.exr: B of the compare views from the start (read and size-checked by the caller).
    std::shared_ptr<const Image> compare_image;
    std::string compare_path;
};

// Runs the viewer until the window closes; returns the exit code (0). Throws pv::Error when there is no display,
// no OpenGL 3.3 context, or the scene cannot be loaded.
int run_viewer(const ViewerOptions& options);

}  // namespace pv::ui
