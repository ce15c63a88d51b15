// app/cmd_bench.cpp: `pathview bench`: speed against error. Renders (or loads) a reference, then for each
// configuration and seed renders a doubling series of spp until the time budget, measures error and speed at
// each power-of-two spp, and reports a table, equal-time comparison, log-log slopes, CSV and SVG. With --rays it
// also measures Embree's raw ray rate on the same scene and ray mix (app/bench/raybench.h) and the path tracer's
// fraction of it. Benchmarks report figures; they never fail on time.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "app/bench.h"
#include "app/bench/raybench.h"
#include "app/bench/scene_gen.h"
#include "app/commands.h"
#include "core/aov.h"
#include "core/denoise_atrous.h"
#include "core/denoise_nfor.h"
#include "core/error.h"
#include "core/file_io.h"
#include "core/image_io.h"
#include "core/renderer.h"
#include "core/scene_file.h"

namespace pv::app {
namespace {

struct BenchOptions {
    CommonOptions common;
    std::string reference;  // EXR to load
    uint32_t reference_spp = 4096;
    SamplerKind reference_sampler = SamplerKind::Independent;
    std::string reference_sampler_name = "independent";
    std::string save_reference;
    double budget = 0.5;  // seconds of rendering per (configuration, seed)
    std::string configs = "all";
    int seeds = 4;
    uint32_t max_spp = 1u << 16;
    std::string csv = "pathview-bench.csv", svg = "pathview-bench.svg";
    std::string title;
    bool rays = false, rays_only = false, scaling = false;
    double rays_seconds = 2.0;
    int rays_rounds = 3;
    std::string clock = "cpu";  // process CPU seconds / threads, or "wall"
    bool quiet = false;
    bool denoise = false;  // denoised columns: a-trous and NFOR at every point
};

// One render pass; returns its duration by the chosen clock (wall, or process CPU time / threads).
double timed_pass(Renderer& r, bool cpu_clock) {
    const double c0 = process_cpu_seconds();
    const double w0 = r.stats().seconds;
    r.render_pass();
    return cpu_clock ? (process_cpu_seconds() - c0) / r.threads() : r.stats().seconds - w0;
}

class Progress {
public:
    explicit Progress(bool enabled) : m_enabled(enabled && isatty(STDERR_FILENO)) {}
    void draw(double fraction, const std::string& what) {
        if (!m_enabled) return;
        const auto now = std::chrono::steady_clock::now();
        if (fraction < 1.0 && std::chrono::duration<double>(now - m_last).count() < 0.1) return;
        m_last = now;
        const int width = 30, filled = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * width);
        std::fprintf(stderr, "\r[%s%s] %3d%%  %-48.48s", std::string(size_t(filled), '=').c_str(),
                     std::string(size_t(width - filled), ' ').c_str(), int(std::clamp(fraction, 0.0, 1.0) * 100),
                     what.c_str());
        std::fflush(stderr);
    }
    void done() {
        if (m_enabled) std::fprintf(stderr, "\r%90s\r", "");
    }

private:
    bool m_enabled;
    std::chrono::steady_clock::time_point m_last{};
};

std::shared_ptr<Scene> load_bench_scene(const CommonOptions& o) {
    if (auto generated = generated_scene(o.scene)) return std::make_shared<Scene>(std::move(*generated));
    return std::make_shared<Scene>(load_scene(scene_path(o)));
}

// ---- Reference

struct Reference {
    Image image;
    double expected_rel_mse = -1.0;  // its own estimated error (< 0: unknown)
    std::string origin;
};

Reference make_reference(const BenchOptions& o, Renderer& renderer, const CameraDesc& camera, Progress& progress) {
    Reference ref;
    if (!o.reference.empty()) {
        Metadata md;
        ref.image = read_exr(o.reference, &md);
        if (ref.image.width != o.common.width || ref.image.height != o.common.height)
            throw Error(o.reference + ": the reference is " + std::to_string(ref.image.width) + "x" +
                        std::to_string(ref.image.height) + "; expected " + std::to_string(o.common.width) + "x" +
                        std::to_string(o.common.height) + " (--width/--height)");
        if (auto it = md.find("pathview:expected_rel_mse"); it != md.end())
            ref.expected_rel_mse = std::stod(it->second);
        ref.origin = o.reference + (md.count("pathview:spp") ? " (" + md["pathview:spp"] + " spp)" : "");
        return ref;
    }
    // Two independent halves (seeds apart from the measured renders'), averaged. Their difference estimates the
    // reference's own error for any sampler: E[(A - B)^2] = 2 var(half) and var((A + B)/2) = var(half)/2, so the
    // average's relMSE is about relMSE(A, B) / 4.
    RenderSettings s = o.common.settings;
    s.sampler = o.reference_sampler;
    const uint32_t half_spp = std::max(1u, o.reference_spp / 2);
    Image halves[2];
    double seconds = 0.0;
    for (int h = 0; h < 2; ++h) {
        s.seed = 0x7265660u + o.common.settings.seed + uint32_t(h) * 0x9e3779b9u;
        renderer.restart(camera, s, o.common.width, o.common.height);
        while (renderer.stats().spp < half_spp) {
            renderer.render_pass();
            progress.draw(0.0, "reference " + std::to_string(h * half_spp + renderer.stats().spp) + "/" +
                                   std::to_string(2 * half_spp) + " spp");
        }
        halves[h] = renderer.film().mean();
        seconds += renderer.stats().seconds;
    }
    ref.image = halves[0];
    for (size_t i = 0; i < ref.image.rgb.size(); ++i) ref.image.rgb[i] = 0.5f * (halves[0].rgb[i] + halves[1].rgb[i]);
    ref.expected_rel_mse = compare_images(halves[0], halves[1]).rel_mse / 4.0;
    char buf[200];
    std::snprintf(buf, sizeof buf, "rendered: 2 x %u spp (%s sampler, %s), %.1f s", half_spp, sampler_name(s.sampler),
                  s.describe().c_str(), seconds);
    ref.origin = buf;
    if (!o.save_reference.empty()) {
        Metadata md = render_metadata(renderer);
        md["pathview:expected_rel_mse"] = std::to_string(ref.expected_rel_mse);
        md["pathview:spp"] = std::to_string(2 * half_spp);
        md["pathview:reference"] = ref.origin;
        write_exr(o.save_reference, ref.image, md);
    }
    return ref;
}

// ---- Convergence series

BenchPoint summarise(const std::vector<BenchSample>& samples) {
    BenchPoint p;
    p.spp = samples.front().spp;
    p.seeds = static_cast<int>(samples.size());
    std::vector<double> t, rel, rmse, mape, trimmed;
    double rays = 0, paths = 0, vertices = 0, secs = 0;
    for (const BenchSample& s : samples) {
        t.push_back(s.seconds);
        rel.push_back(s.error.rel_mse);
        rmse.push_back(s.error.rmse);
        mape.push_back(s.error.mape);
        trimmed.push_back(s.rel_mse_trimmed);
        rays += s.rays + s.shadow_rays;
        paths += s.paths;
        vertices += s.vertices;
        secs += s.seconds;
    }
    p.seconds = spread_of(t);
    p.rel_mse = spread_of(rel);
    p.rmse = spread_of(rmse);
    p.mape = spread_of(mape);
    p.rel_mse_trimmed = spread_of(trimmed);
    p.mrays_per_s = secs > 0 ? rays / secs * 1e-6 : 0.0;
    p.mean_path_length = paths > 0 ? vertices / paths : 0.0;
    p.rays_per_sample = paths > 0 ? rays / paths : 0.0;
    p.denoised = samples.front().nfor_seconds > 0.0;
    if (p.denoised) {
        std::vector<double> ra, ta, rn, tn;
        for (const BenchSample& s : samples) {
            ra.push_back(s.rel_mse_atrous);
            ta.push_back(s.atrous_seconds);
            rn.push_back(s.rel_mse_nfor);
            tn.push_back(s.nfor_seconds);
        }
        p.rel_mse_atrous = spread_of(ra);
        p.atrous_seconds = spread_of(ta);
        p.rel_mse_nfor = spread_of(rn);
        p.nfor_seconds = spread_of(tn);
    }
    return p;
}

// Renders seed after seed of one configuration. The first seed fixes the spp series: powers of two while the next
// doubling fits in the budget (from the time the current spp took); the other seeds render the same series.
BenchSeries run_series(const BenchOptions& o, const BenchConfig& config, Renderer& renderer, const CameraDesc& camera,
                       const Image& reference, Progress& progress, double progress_base, double progress_step) {
    std::vector<std::vector<BenchSample>> by_point;
    uint32_t last_spp = 0;
    FeatureImage features;  // the camera's first-hit features, for --denoise (same for every seed)
    if (o.denoise) {
        renderer.restart(camera, config.settings, o.common.width, o.common.height);
        features = render_features(renderer.traceable(), renderer.camera(), o.common.width, o.common.height);
    }
    for (int seed = 0; seed < o.seeds; ++seed) {
        RenderSettings s = config.settings;
        s.seed = o.common.settings.seed + 1u + uint32_t(seed);
        renderer.restart(camera, s, o.common.width, o.common.height);
        size_t point = 0;
        double seconds = 0.0;
        for (uint32_t target = 1;; target *= 2) {
            while (renderer.stats().spp < target && !renderer.converged())
                seconds += timed_pass(renderer, o.clock == "cpu");
            const RenderStats& st = renderer.stats();
            BenchSample smp;
            smp.spp = st.spp;
            smp.seconds = seconds;
            const Image mean = renderer.film().mean();
            smp.error = compare_images(mean, reference);
            smp.rel_mse_trimmed = compare_images(mean, reference, kMetricEps, 0.001).rel_mse;
            if (o.denoise) {
                const auto t0 = std::chrono::steady_clock::now();
                const Image atrous = denoise_atrous(mean, renderer.film().variance_of_mean(), features);
                smp.atrous_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                smp.rel_mse_atrous = compare_images(atrous, reference).rel_mse;
                NforStats nfor;
                smp.rel_mse_nfor = compare_images(denoise_nfor(renderer.film(), features, &nfor), reference).rel_mse;
                smp.nfor_seconds = nfor.seconds;
            }
            smp.rays = double(st.rays);
            smp.shadow_rays = double(st.shadow_rays);
            smp.paths = double(st.paths);
            smp.vertices = double(st.vertices);
            if (by_point.size() <= point) by_point.emplace_back();
            by_point[point++].push_back(smp);
            const double f = seed == 0 ? std::min(1.0, seconds / o.budget) : double(point) / by_point.size();
            progress.draw(progress_base + progress_step * (seed + f) / o.seeds,
                          config.name + " seed " + std::to_string(seed + 1) + "/" + std::to_string(o.seeds) + ", " +
                              std::to_string(st.spp) + " spp");
            const bool last = seed == 0 ? (seconds * 2.0 > o.budget || target * 2 > o.max_spp || renderer.converged())
                                        : target >= last_spp;
            if (last) {
                if (seed == 0) last_spp = target;
                break;
            }
        }
    }
    BenchSeries series;
    series.config = config;
    std::vector<double> spp, secs, rel;
    for (const auto& samples : by_point) {
        series.points.push_back(summarise(samples));
        const BenchPoint& p = series.points.back();
        // Fits skip spp < 4, where every estimator is still pre-asymptotic (TEST-CATALOG 4.8).
        if (p.spp >= 4) {
            spp.push_back(p.spp);
            secs.push_back(p.seconds.mean);
            rel.push_back(p.rel_mse.mean);
        }
    }
    series.slope_spp = fit_loglog(spp, rel);
    series.slope_time = fit_loglog(secs, rel);
    return series;
}

void print_summary(const std::vector<BenchSeries>& all, const Reference& ref) {
    // Equal time: the longest time every configuration reached, relMSE interpolated log-log between its points.
    double t_common = 1e300;
    for (const BenchSeries& s : all) t_common = std::min(t_common, s.points.back().seconds.mean);
    const BenchSeries* baseline = &all.front();
    for (const BenchSeries& s : all)
        if (s.config.name == "mis/rr/ind") baseline = &s;
    auto at_t = [&](const BenchSeries& s, bool trimmed) {
        std::vector<double> x, y;
        for (const BenchPoint& p : s.points)
            x.push_back(p.seconds.mean), y.push_back(trimmed ? p.rel_mse_trimmed.mean : p.rel_mse.mean);
        return interpolate_loglog(x, y, t_common).value_or(y.back());
    };
    const double base_err = at_t(*baseline, false), base_trim = at_t(*baseline, true);
    std::printf("\n### Equal time: relMSE at %.3f s (interpolated log-log between power-of-two spp points)\n\n",
                t_common);
    std::printf(
        "| config | relMSE at %.3g s | relative to %s | trimmed relMSE (top 0.1%% dropped) | relative | spp "
        "reached in budget | seconds | slope vs spp | slope vs time | Mrays/s | rays/sample | path length |\n",
        t_common, baseline->config.name.c_str());
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const BenchSeries& s : all) {
        const BenchPoint& last = s.points.back();
        const double e = at_t(s, false), et = at_t(s, true);
        std::printf("| %s | %.4g | %.3f | %.4g | %.3f | %u | %.3f | %.2f | %.2f | %.2f | %.2f | %.2f |\n",
                    s.config.name.c_str(), e, e / base_err, et, et / base_trim, last.spp, last.seconds.mean,
                    s.slope_spp.slope, s.slope_time.slope, last.mrays_per_s, last.rays_per_sample,
                    last.mean_path_length);
    }
    // The reference check: its own error must be far below the smallest error measured against it.
    double smallest = 1e300;
    for (const BenchSeries& s : all)
        for (const BenchPoint& p : s.points) smallest = std::min(smallest, p.rel_mse.mean);
    std::printf("\nReference: %s\n", ref.origin.c_str());
    if (ref.expected_rel_mse < 0) {
        std::printf(
            "WARNING: the reference's own error is unknown (no pathview:expected_rel_mse in the EXR); "
            "errors below its noise cannot be trusted.\n");
    } else {
        const double ratio = ref.expected_rel_mse / smallest;
        std::printf("Reference's estimated relMSE %.3g = %.1f%% of the smallest measured relMSE %.3g: %s\n",
                    ref.expected_rel_mse, 100.0 * ratio, smallest,
                    ratio <= 0.1 ? "converged enough (<= 10%)"
                                 : "WARNING: NOT converged enough (> 10%): the smallest errors and the slopes are "
                                   "inflated by the reference's noise; raise --reference-spp");
    }
}

// ---- Ray-rate ceiling

void rays_section(const BenchOptions& o, std::shared_ptr<const Scene> scene, const CameraDesc& camera,
                  Progress& progress) {
    std::vector<int> thread_counts;
    Renderer probe(scene, o.common.threads);
    const int n = probe.threads();
    if (o.scaling && n > 1) thread_counts.push_back(1);
    thread_counts.push_back(n);
    RenderSettings settings = o.common.settings;
    std::printf("\n### Ray-rate ceiling: %s, %dx%d, %s, %s clock\n\n", scene->source.c_str(), o.common.width,
                o.common.height, settings.describe().c_str(), o.clock.c_str());
    std::printf("BVH: %zu triangles, build %.3f s, %.2f MiB (Embree memory monitor)\n\n", scene->triangle_count(),
                probe.traceable().accel().stats().build_seconds,
                double(probe.traceable().accel().stats().bytes) / (1024.0 * 1024.0));
    std::printf(
        "| threads | round | path tracer Mrays/s | Embree camera | Embree bounce | Embree shadow | Embree on the "
        "path tracer's mix | fraction of ceiling | minimal kernel Mrays/s | its fraction |\n"
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    std::vector<std::pair<int, double>> medians, minimal_medians;
    for (int threads : thread_counts) {
        Renderer r(scene, threads);
        std::vector<double> fractions, minimal_fractions;
        double pt_sum = 0, ceil_sum = 0, mk_sum = 0, mk_ceil_sum = 0;
        for (int round = 0; round < o.rays_rounds; ++round) {
            progress.draw(double(round) / o.rays_rounds, "ray rates, " + std::to_string(threads) + " threads");
            r.restart(camera, settings, o.common.width, o.common.height);
            r.render_pass();  // warm-up pass, not counted
            r.restart(camera, settings, o.common.width, o.common.height);
            double seconds = 0.0;
            while (seconds < o.rays_seconds) seconds += timed_pass(r, o.clock == "cpu");
            const RenderStats& st = r.stats();
            const double pt = double(st.rays + st.shadow_rays) / seconds;
            RayMix mix;
            mix.camera = double(st.paths);
            mix.bounce = double(st.rays - st.paths);
            mix.shadow = double(st.shadow_rays);
            RayBenchOptions ro;
            ro.width = o.common.width;
            ro.height = o.common.height;
            ro.threads = threads;
            ro.seconds_per_kind = o.rays_seconds / 3.0;
            ro.seed = 17u + uint32_t(round);
            ro.cpu_clock = o.clock == "cpu";
            const RayRates rates = measure_ray_rates(r.traceable(), r.camera(), ro);
            const double ceiling = rates.mix_rate(mix);
            const MinimalKernelRate mk = measure_minimal_kernel(r.traceable(), r.camera(), ro);
            const double mk_ceiling = rates.mix_rate(mk.mix);
            fractions.push_back(pt / ceiling);
            minimal_fractions.push_back(mk.rays_per_second / mk_ceiling);
            pt_sum += pt;
            ceil_sum += ceiling;
            mk_sum += mk.rays_per_second;
            mk_ceil_sum += mk_ceiling;
            std::printf("| %d | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.3f | %.2f | %.3f |\n", threads, round + 1,
                        pt * 1e-6, rates.camera * 1e-6, rates.bounce * 1e-6, rates.shadow * 1e-6, ceiling * 1e-6,
                        pt / ceiling, mk.rays_per_second * 1e-6, mk.rays_per_second / mk_ceiling);
            std::fflush(stdout);
        }
        std::sort(fractions.begin(), fractions.end());
        std::sort(minimal_fractions.begin(), minimal_fractions.end());
        medians.emplace_back(threads, fractions[fractions.size() / 2]);
        minimal_medians.emplace_back(threads, minimal_fractions[minimal_fractions.size() / 2]);
        std::printf("| %d | mean | %.2f | | | | %.2f | %.3f | %.2f | %.3f |\n", threads, pt_sum / o.rays_rounds * 1e-6,
                    ceil_sum / o.rays_rounds * 1e-6, pt_sum / ceil_sum, mk_sum / o.rays_rounds * 1e-6,
                    mk_sum / mk_ceil_sum);
    }
    std::printf("\n");
    for (size_t i = 0; i < medians.size(); ++i)
        std::printf(
            "Path tracer at %d thread%s: median %.3f of Embree's raw rate on the same ray mix (minimal kernel: "
            "%.3f of the rate on its own mix).\n",
            medians[i].first, medians[i].first == 1 ? "" : "s", medians[i].second, minimal_medians[i].second);
    std::printf(
        "The minimal kernel (white Lambertian, one shadow ray per vertex, PCG numbers, no MIS, roulette, "
        "materials, Sobol or film) bounds what per-ray shading code reaches on this scene.\n");
}

void run(BenchOptions& o) {
    resolve_switches(o.common);
    for (const std::string* out : {&o.csv, &o.svg})
        if (!out->empty()) check_writable(*out);  // before the minutes of measuring, not after them
    o.reference_sampler = *parse_sampler(o.reference_sampler_name);
    Progress progress(!o.quiet);
    std::shared_ptr<Scene> scene = load_bench_scene(o.common);
    const CameraDesc camera = set_up_scene(o.common, *scene);
    const std::string scene_name = scene->source.empty() ? o.common.scene : scene->source;

    if (!o.rays_only) {
        const std::vector<BenchConfig> configs = parse_configs(o.configs, o.common.settings);
        Renderer renderer(scene, o.common.threads);
        std::printf(
            "## pathview bench: %s\n\n%dx%d, %d threads, budget %.3g s (%s clock) per configuration and seed, "
            "%d seeds, max_depth %d, %zu triangles (BVH build %.3f s, %.2f MiB)\n",
            scene_name.c_str(), o.common.width, o.common.height, renderer.threads(), o.budget, o.clock.c_str(), o.seeds,
            o.common.settings.max_depth, scene->triangle_count(), renderer.traceable().accel().stats().build_seconds,
            double(renderer.traceable().accel().stats().bytes) / (1024.0 * 1024.0));
        std::fflush(stdout);
        const Reference ref = make_reference(o, renderer, camera, progress);
        renderer.set_adaptive(o.common.adaptive);  // the measured renders only, not the reference
        std::vector<BenchSeries> all;
        for (size_t i = 0; i < configs.size(); ++i)
            all.push_back(run_series(o, configs[i], renderer, camera, ref.image, progress, double(i) / configs.size(),
                                     1.0 / configs.size()));
        progress.done();
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
            std::snprintf(sub, sizeof sub, " (%dx%d, %d threads, %d seeds)", o.common.width, o.common.height,
                          renderer.threads(), o.seeds);
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
        progress.done();
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
        "Cornell box with a 1M-triangle displaced sphere)");
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
                    "Comma-separated estimator/rr/sampler: estimator bsdf|nee|mis, rr rr|norr, sampler ind|sobol, "
                    "each may be *; or all")
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
    cmd->callback([o] { run(*o); });
}

}  // namespace pv::app
