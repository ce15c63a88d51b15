// app/cmd_view.cpp: `pathview view` (the default subcommand): the interactive viewer (ui/viewer.h).
#include "app/commands.h"
#include "core/base/error.h"
#include "core/image/image_io.h"
#include "core/load/scene_file.h"

#ifdef PATHVIEW_HAS_UI
#include "ui/viewer.h"
#endif

#include <cstdio>
#include <filesystem>

namespace pv::app {
namespace {

struct ViewOptions {
    CommonOptions common;
    std::string snapshot_dir = ".";
    std::string log_file;
    std::string compare;     // an EXR shown as B of the compare views
    float exposure = 0.f;    // the display's, at the start
    DisplayOptions display;  // the view transform at the start, and the OpenColorIO config offered
};

void run(const ViewOptions& o) {
#ifdef PATHVIEW_HAS_UI
    if (!std::filesystem::is_directory(o.snapshot_dir))
        throw Error("--snapshot-dir " + o.snapshot_dir +
                    ": not a folder; expected an existing folder for EXR snapshots");
    ui::ViewerOptions v;
    v.load_scene = [&o] {
        Scene scene = load_scene(scene_path(o.common));
        scene.camera = set_up_scene(o.common, scene);
        return scene;
    };
    v.settings = o.common.settings;
    v.adaptive = o.common.adaptive;
    v.width = o.common.width;
    v.height = o.common.height;
    v.threads = o.common.threads;
    v.snapshot_dir = o.snapshot_dir;
    v.log_file = o.log_file;
    v.display = resolve_display(o.display, ViewTransform::Aces, true);
    v.display.exposure = o.exposure;
    v.ocio_config = offered_ocio_config(o.display, v.display);
    v.ocio_input = o.display.ocio_input;
    if (!o.compare.empty()) {
        // Read before the window opens: an unreadable or wrong-size file is one line and a non-zero exit.
        auto b = std::make_shared<Image>(read_exr(o.compare));
        if (b->width != o.common.width || b->height != o.common.height)
            throw Error("--compare " + o.compare + ": " + std::to_string(b->width) + "x" + std::to_string(b->height) +
                        " pixels; expected the image's " + std::to_string(o.common.width) + "x" +
                        std::to_string(o.common.height) + " (--width, --height)");
        v.compare_image = std::move(b);
        v.compare_path = o.compare;
    }
    ui::run_viewer(v);
#else
    (void)o;
    throw Error("this pathview was built without the viewer (PATHVIEW_BUILD_UI=OFF); use `pathview render`");
#endif
}

}  // namespace

void add_view_command(CLI::App& app, CLI::App*& view_cmd) {
    auto o = std::make_shared<ViewOptions>();
    view_cmd = app.add_subcommand("view", "Open the interactive viewer (the default)");
    add_common_options(*view_cmd, o->common);
    view_cmd->add_option("--snapshot-dir", o->snapshot_dir, "Folder for EXR snapshots (Ctrl+S)")->capture_default_str();
    view_cmd->add_option("--compare", o->compare,
                         "Show this EXR as B of the compare views (split, flip, difference) with the live relMSE "
                         "against it; it must have the image's size");
    add_exposure_option(*view_cmd, o->exposure, "Display exposure in stops at the start (display only)");
    add_display_options(*view_cmd, o->display, "aces");
    view_cmd->add_option("--log-file", o->log_file,
                         "Log restarts (with reasons), snapshots and timings to this file, one line each");
    view_cmd->callback([o] {
        resolve_switches(o->common);
        run(*o);
    });
}

}  // namespace pv::app
