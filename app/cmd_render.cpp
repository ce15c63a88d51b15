// app/cmd_render.cpp: `pathview render`: headless rendering to EXR or PNG, with a progress bar and a summary.
#include "app/commands.h"

#include "core/error.h"
#include "core/file_io.h"
#include "core/image_io.h"
#include "core/renderer.h"
#include "core/scene_file.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <mutex>

namespace pv::app {
namespace {

struct RenderOptions {
    CommonOptions common;
    std::optional<int> spp;
    std::optional<double> seconds;
    std::vector<std::string> outs;  // every -o: the same render written to each
    float exposure = 0.f;
    bool quiet = false;
};

void progress_bar(double fraction, uint32_t spp, double seconds) {
    const int width = 30;
    const int filled = static_cast<int>(std::min(1.0, fraction) * width);
    std::fprintf(stderr, "\r[%.*s%.*s] %3d%%  %u spp  %.1f s", filled, "==============================", width - filled,
                 "                              ", static_cast<int>(std::min(1.0, fraction) * 100.0), spp, seconds);
    std::fflush(stderr);
}

void run(RenderOptions& o) {
    resolve_switches(o.common);
    if (!o.spp && !o.seconds) o.spp = 64;
    const std::string path = scene_path(o.common);
    for (const std::string& out : o.outs) {
        const std::string ext = std::filesystem::path(out).extension().string();
        if (ext != ".exr" && ext != ".png" && ext != ".EXR" && ext != ".PNG")
            throw Error(out + ": unknown image format '" + ext + "'; expected .exr or .png");
        check_writable(out);  // before the render, not after it
    }
    check_film_memory(o.common.width, o.common.height);

    const bool tty = !o.quiet && isatty(STDERR_FILENO);
    const auto load_start = std::chrono::steady_clock::now();
    auto since_load = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count(); };
    // Load on a worker thread; on a terminal, show the elapsed time meanwhile (the OBJ parser reports no fraction).
    auto loading = std::async(std::launch::async, [&path] { return load_scene(path); });
    if (tty)
        while (loading.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready)
            std::fprintf(stderr, "\rpathview: loading %s  %.1f s", path.c_str(), since_load());
    auto scene = std::make_shared<Scene>(loading.get());
    if (tty) std::fprintf(stderr, "\r\033[K");
    apply_scene_overrides(o.common, *scene);
    const double load_seconds = since_load();
    for (const std::string& w : scene->warnings) std::fprintf(stderr, "pathview: warning: %s\n", w.c_str());
    CameraDesc camera = scene->camera;
    apply_camera_overrides(o.common, *scene, camera);

    // BVH build progress from Embree's build threads, drawn at most every 2 percent.
    std::mutex progress_mutex;
    int drawn = -1;
    auto build_progress = [&](double fraction) {
        const int percent = static_cast<int>(fraction * 100.0);
        std::lock_guard<std::mutex> lock(progress_mutex);
        if (percent < drawn + 2) return;
        drawn = percent;
        std::fprintf(stderr, "\rpathview: building the BVH of %zu triangles  %3d%%", scene->triangle_count(), percent);
    };
    Renderer renderer(scene, o.common.threads, tty ? std::function<void(double)>(build_progress) : nullptr);
    if (tty) std::fprintf(stderr, "\r\033[K");
    if (!o.quiet) {
        const AccelStats& as = renderer.accel().stats();
        std::fprintf(stderr, "pathview: loaded %zu triangles in %.2f s; BVH %.2f s, %.1f MiB (%.0f bytes/triangle)\n",
                     scene->triangle_count(), load_seconds, as.build_seconds, double(as.bytes) / (1 << 20),
                     double(as.bytes) / double(std::max<size_t>(1, scene->triangle_count())));
    }
    renderer.restart(camera, o.common.settings, o.common.width, o.common.height);
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    double last_draw = -1.0;
    for (;;) {
        const double t = elapsed();
        const RenderStats& st = renderer.stats();
        if (o.spp && st.spp >= static_cast<uint32_t>(*o.spp)) break;
        if (o.seconds && t >= *o.seconds && st.spp > 0) break;
        if (tty && t - last_draw > 0.1) {
            const double f = o.spp ? double(st.spp) / *o.spp : t / *o.seconds;
            progress_bar(f, st.spp, t);
            last_draw = t;
        }
        renderer.render_pass();
    }
    if (tty) {
        progress_bar(1.0, renderer.stats().spp, elapsed());
        std::fprintf(stderr, "\n");
    }

    Image image = renderer.film().mean();
    if (o.exposure != 0.f)
        for (float& v : image.rgb) {
            // Overflow saturates: a file never holds Inf (the film's means are finite and non-negative).
            const float s = v * std::exp2(o.exposure);
            v = std::isfinite(s) ? s : std::numeric_limits<float>::max();
        }
    std::string written;
    for (const std::string& out : o.outs) {
        write_image(out, image, render_metadata(renderer));
        written += (written.empty() ? "" : ", ") + out;
    }

    const RenderStats& st = renderer.stats();
    const double secs = std::max(st.seconds, 1e-9);
    if (renderer.settings().max_depth < RenderSettings{}.max_depth)
        std::fprintf(stderr, "pathview: note: --max-depth %d truncates paths, so the image is biased (darker) "
                     "compared with the unbounded default\n", renderer.settings().max_depth);
    std::printf("pathview: %u spp in %.2f s, %s paths/s, %s rays/s (%s closest-hit + %s shadow), %.2f rays/path, "
                "%llu dropped samples, %d threads, %s -> %s\n",
                st.spp, st.seconds, format_si(double(st.paths) / secs).c_str(),
                format_si(double(st.rays + st.shadow_rays) / secs).c_str(), format_si(double(st.rays) / secs).c_str(),
                format_si(double(st.shadow_rays) / secs).c_str(),
                double(st.rays + st.shadow_rays) / double(std::max<uint64_t>(st.paths, 1)),
                static_cast<unsigned long long>(st.dropped), renderer.threads(), renderer.settings().describe().c_str(),
                written.c_str());
}

}  // namespace

void add_render_command(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene headless to an OpenEXR (linear FLOAT RGB + metadata) "
                                                 "or PNG (tone-mapped sRGB) file");
    add_common_options(*cmd, o->common);
    auto* spp = cmd->add_option("--spp", o->spp, "Samples per pixel (default 64 when --time is not given)")
                    ->check(CLI::Range(1, 1 << 30));
    cmd->add_option("--time", o->seconds, "Render for this many seconds (whole passes)")
        ->check(finite_range(0, 1e9))
        ->excludes(spp);
    cmd->add_option("-o,--output", o->outs, "Output file: .exr or .png; repeat -o to write several")
        ->required()
        ->take_all();
    cmd->add_option("--exposure", o->exposure, "Exposure in stops applied before writing")
        ->check(finite_range(-64, 64))
        ->capture_default_str();
    cmd->add_flag("-q,--quiet", o->quiet, "No progress bar");
    cmd->callback([o] { run(*o); });
}

}  // namespace pv::app
