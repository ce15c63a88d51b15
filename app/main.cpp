// app/main.cpp: the pathview executable. Subcommands: view (the default), render, bench.
// The only top-level catch: bad input prints one line and exits non-zero.
#include <algorithm>
#include <cstdio>
#include <cstring>

#include "app/commands.h"
#include "core/base/error.h"
#include "core/base/version.h"

int main(int argc, char** argv) {
    CLI::App app{
        "pathview: an interactive CPU path tracer (Embree BVH, OBJ/MTL scenes, OpenEXR output).\n"
        "  pathview [SCENE] [options]        open the viewer (same as `pathview view`)\n"
        "  pathview render [SCENE] -o OUT    render headless to .exr or .png\n"
        "  pathview bench [SCENE]            speed against error\n"
        "  pathview merge OUT PART...        merge partial renders (render --samples START:COUNT)\n"
        "SCENE is a .json scene file, an .obj, a .gltf or a .glb; default: the built-in Cornell box.",
        "pathview"};
    app.set_version_flag("--version", std::string("pathview ") + pv::kVersion);
    CLI::App* view_cmd = nullptr;
    pv::app::add_view_command(app, view_cmd);
    pv::app::add_render_command(app);
    pv::app::add_bench_command(app);
    pv::app::add_merge_command(app);
    app.require_subcommand(1, 1);

    // `pathview [SCENE] [options]` means `pathview view [SCENE] [options]`.
    std::vector<std::string> args(argv + 1, argv + argc);
    const bool top_level_flag = !args.empty() && (args[0] == "-h" || args[0] == "--help" || args[0] == "--version");
    if (!top_level_flag &&
        (args.empty() || (args[0] != "view" && args[0] != "render" && args[0] != "bench" && args[0] != "merge")))
        args.insert(args.begin(), "view");
    std::reverse(args.begin(), args.end());  // CLI11 takes the arguments reversed

    try {
        try {
            app.parse(args);
        } catch (const CLI::ParseError& e) {
            return app.exit(e);
        }
    } catch (const pv::Error& e) {
        std::fprintf(stderr, "pathview: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pathview: internal error: %s\n", e.what());
        return 2;
    }
    return 0;
}
