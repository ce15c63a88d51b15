// app/cmd_bench.cpp: `pathview bench`: speed against error. Renders (or loads) a reference, then for each
// configuration and seed renders a doubling series of spp until the time budget, measures error and speed at
// each power-of-two spp, and reports a table, equal-time comparison, log-log slopes, CSV and SVG. With --rays it
// also measures Embree's raw ray rate on the same scene and ray mix (app/bench/raybench.h) and the path tracer's
// fraction of it. Benchmarks report figures; they never fail on time.
// The parts: bench/reference.h, bench/series.h, bench/ray_ceiling.h, and bench_report.cpp (tables, CSV, SVG).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>

#include "app/bench.h"
#include "app/bench/options.h"
#include "app/bench/ray_ceiling.h"
#include "app/bench/reference.h"
#include "app/bench/scene_gen.h"
#include "app/bench/series.h"
#include "app/commands.h"
#include "app/progress.h"
#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/frame/renderer.h"
#include "core/load/scene_file.h"
#include "core/render/light_tree.h"
#include "core/sampling/rng.h"

namespace pv::app {
namespace {

std::shared_ptr<Scene> load_bench_scene(const CommonOptions& o) {
    if (auto generated = generated_scene(o.scene)) return std::make_shared<Scene>(std::move(*generated));
    return std::make_shared<Scene>(load_scene(scene_path(o)));
}

// --light-tree: builds the light tree (core/render/light_tree.h) over 10^2..10^6 random emissive triangles (a cube of
// side 10, sides 0.01..0.1, random orientations, powers over four decades) and prints the build's time (the best of a
// few builds, CPU of this thread) and memory. Figures, no assertions.
void light_tree_scaling() {
    std::printf("## pathview bench --light-tree: build time and memory of the light tree\n\n");
    std::printf("| emissive triangles | nodes | depth | build ms (best of %d) | memory MiB | bytes per emitter |\n", 3);
    std::printf("|---:|---:|---:|---:|---:|---:|\n");
    for (const int n : {100, 1000, 10000, 100000, 1000000}) {
        Pcg32 g(uint64_t(n), 1);
        std::vector<LightBounds> bounds;
        bounds.reserve(size_t(n));
        auto u3 = [&] { return vec3(g.next_float(), g.next_float(), g.next_float()); };
        for (int i = 0; i < n; ++i) {
            const vec3 c = 10.f * u3();
            const float s = 0.01f + 0.09f * g.next_float();
            const vec3 p0 = c + s * (2.f * u3() - 1.f), p1 = c + s * (2.f * u3() - 1.f),
                       p2 = c + s * (2.f * u3() - 1.f);
            const float phi = std::pow(10.f, 4.f * g.next_float()) * 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
            bounds.push_back(triangle_light_bounds(p0, p1, p2, phi, i % 3 == 0));
        }
        double best = 1e30;
        LightTree tree;
        for (int rep = 0; rep < 3; ++rep) {
            timespec t0{}, t1{};
            clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
            tree = LightTree(bounds);
            clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
            best = std::min(best, double(t1.tv_sec - t0.tv_sec) * 1e3 + double(t1.tv_nsec - t0.tv_nsec) * 1e-6);
        }
        const double bytes = double(tree.memory_bytes());
        std::printf("| %d | %zu | %d | %.2f | %.2f | %.0f |\n", n, tree.node_count(), tree.depth(), best,
                    bytes / (1024.0 * 1024.0), bytes / n);
    }
}

void run(BenchOptions& o) {
    if (o.light_tree) {
        light_tree_scaling();
        return;
    }
    resolve_switches(o.common);
    for (uint32_t spp : o.denoise_spp) {
        if ((spp & (spp - 1)) != 0)
            throw Error("--denoise-spp: " + std::to_string(spp) +
                        " is not a point of the series (the points are at 1, 2, 4, 8, ... spp)");
        if (spp > o.max_spp)
            throw Error("--denoise-spp: " + std::to_string(spp) + " is beyond --max-spp " + std::to_string(o.max_spp) +
                        ", so the series never reaches it");
    }
    if (!o.denoise_spp.empty()) o.denoise = true;
    for (const std::string* out : {&o.csv, &o.svg})
        if (!out->empty()) check_writable(*out);  // before the minutes of measuring, not after them
    o.reference_sampler = *parse_sampler(o.reference_sampler_name);
    ProgressBar progress(!o.quiet);
    std::shared_ptr<Scene> scene = load_bench_scene(o.common);
    const CameraDesc camera = set_up_scene(o.common, *scene);
    const std::string scene_name = scene->source.empty() ? o.common.scene : scene->source;

    if (!o.rays_only) {
        const std::vector<BenchConfig> configs = parse_configs(o.configs, o.common.settings);
        Renderer renderer(scene, o.common.threads);
        std::printf(
            "## pathview bench: %s\n\n%dx%d, %d thread%s, budget %.3g s (%s clock) per configuration and seed, "
            "%d seeds, max_depth %d, %zu triangles (BVH build %.3f s, %.2f MiB)\n",
            scene_name.c_str(), o.common.width, o.common.height, renderer.threads(), renderer.threads() == 1 ? "" : "s",
            o.budget, o.clock.c_str(), o.seeds, o.common.settings.max_depth, scene->triangle_count(),
            renderer.traceable().accel().stats().build_seconds,
            double(renderer.traceable().accel().stats().bytes) / (1024.0 * 1024.0));
        std::fflush(stdout);
        const Reference ref = make_reference(o, renderer, camera, progress);
        renderer.set_adaptive(o.common.adaptive);  // the measured renders only, not the reference
        std::vector<BenchSeries> all;
        for (size_t i = 0; i < configs.size(); ++i)
            all.push_back(run_series(o, configs[i], renderer, camera, ref.image, progress, double(i) / configs.size(),
                                     1.0 / configs.size()));
        progress.clear();
        std::printf("\n### Every point (mean over %d seeds; relMSE eps 0.01, no trimming)\n\n", o.seeds);
        print_points_table(all);
        if (o.denoise) {
            std::printf(
                "\n### Denoised (relMSE of the denoised image against the reference; the noisy column is "
                "the estimator's own; filter times are wall seconds, not part of the render time)\n\n");
            print_denoise_table(all);
        }
        print_summary(all, ref);
        if (!o.csv.empty()) write_csv(o.csv, scene_name, all);
        if (!o.svg.empty()) {
            char sub[200];
            std::snprintf(sub, sizeof sub, " (%dx%d, %d thread%s, %d seeds)", o.common.width, o.common.height,
                          renderer.threads(), renderer.threads() == 1 ? "" : "s", o.seeds);
            // "assets/mis-plates/scene.json" is better named by its folder.
            std::filesystem::path sp(scene_name);
            const std::string name =
                sp.filename() == "scene.json" ? sp.parent_path().filename().string() : sp.filename().string();
            write_svg(o.svg, (o.title.empty() ? name : o.title) + sub, all);
        }
        if (!o.csv.empty() || !o.svg.empty())
            std::printf("\nWrote%s%s%s%s\n", o.csv.empty() ? "" : " ", o.csv.c_str(), o.svg.empty() ? "" : " ",
                        o.svg.c_str());
    }
    if (o.rays || o.rays_only) {
        rays_section(o, scene, camera, progress);
        progress.clear();
    }
}

}  // namespace

void add_bench_command(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    o->common.width = o->common.height = 128;
    CLI::App* cmd = app.add_subcommand(
        "bench",
        "Speed against error: a reference, then per configuration and seed a doubling spp series within a "
        "time budget; table, equal-time comparison, slopes, CSV and SVG. Default: the built-in Cornell box "
        "at 128x128, 12 configurations x 4 seeds x 0.5 s, a 4096 spp reference (about a minute on 2 cores). SCENE may "
        "also be large-mesh (generated: the "
        "Cornell box with a 1M-triangle displaced sphere), many-lights (assets/many-lights: 320 small lamps), "
        "compressed-instanced (assets/compressed-instanced: a compressed mesh placed 400 times; load time and memory "
        "printed) or fog-box (assets/fog-box: the Cornell box in fog with a point lamp)");
    add_common_options(*cmd, o->common);
    auto* ref = cmd->add_option("--reference", o->reference, "Reference EXR (same size) instead of rendering one");
    cmd->add_option("--reference-spp", o->reference_spp, "Samples per pixel of the rendered reference")
        ->check(CLI::Range(1u, 1u << 30))
        ->capture_default_str()
        ->excludes(ref);
    cmd->add_option("--reference-sampler", o->reference_sampler_name, "Sampler of the rendered reference")
        ->check(CLI::IsMember({"independent", "sobol"}))
        ->capture_default_str();
    cmd->add_option("--save-reference", o->save_reference,
                    "Write the rendered reference to this EXR (with its "
                    "estimated error in the metadata)");
    cmd->add_option("--budget", o->budget, "Seconds of rendering per configuration and seed")
        ->check(CLI::Range(1e-3, 1e6))
        ->capture_default_str();
    cmd->add_option("--configs", o->configs,
                    "Comma-separated estimator/rr/sampler[/light-sampler]: estimator bsdf|nee|mis, rr rr|norr, "
                    "sampler ind|sobol, light sampler power|tree (default: --light-sampler's), each may be *; or all")
        ->capture_default_str();
    cmd->add_option("--seeds", o->seeds, "Seeds per configuration")->check(CLI::Range(1, 1000))->capture_default_str();
    cmd->add_option("--max-spp", o->max_spp, "Stop a series at this spp")
        ->check(CLI::Range(1u, 1u << 30))
        ->capture_default_str();
    cmd->add_option("--csv", o->csv, "CSV output (empty: none)")->capture_default_str();
    cmd->add_option("--svg", o->svg, "SVG plot output (empty: none)")->capture_default_str();
    cmd->add_option("--title", o->title, "Title of the plot (default: the scene file name)");
    cmd->add_flag("--rays", o->rays,
                  "Also measure Embree's raw ray rate on the same scene and ray mix, and the path "
                  "tracer's fraction of it (uses --light-sampling/--mis/--rr/--sampler)");
    cmd->add_flag("--rays-only", o->rays_only, "Only the ray-rate section");
    cmd->add_flag("--light-tree", o->light_tree,
                  "Only the light tree's build time and memory for 10^2..10^6 random emissive triangles");
    cmd->add_flag("--scaling", o->scaling, "Ray-rate section at 1 thread as well as --threads");
    cmd->add_option("--rays-seconds", o->rays_seconds, "Seconds of path tracing per round of the ray-rate section")
        ->check(CLI::Range(0.01, 1e6))
        ->capture_default_str();
    cmd->add_option("--rays-rounds", o->rays_rounds,
                    "Rounds of the ray-rate section (path tracer and Embree "
                    "alternate; the median fraction is reported)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    cmd->add_option("--clock", o->clock,
                    "cpu: time is process CPU seconds / threads (equals the wall clock on an idle "
                    "machine; other processes sharing the cores do not inflate it); wall: the "
                    "wall clock")
        ->check(CLI::IsMember({"wall", "cpu"}))
        ->capture_default_str();
    cmd->add_flag("-q,--quiet", o->quiet, "No progress bar");
    cmd->add_flag("--denoise", o->denoise,
                  "At every point also denoise (a-trous and NFOR, with first-hit features) "
                  "and report the denoised relMSE and the filter times in their own table and the CSV (slow: use "
                  "with one --configs entry)");
    cmd->add_option("--denoise-spp", o->denoise_spp,
                    "Denoise only at these points (comma-separated powers of two, e.g. 16 or 16,32; implies "
                    "--denoise): NFOR at every doubling is slow at 512x512")
        ->delimiter(',')
        ->check(CLI::Range(1u, 1u << 30));
    cmd->callback([o] { run(*o); });
}

}  // namespace pv::app
