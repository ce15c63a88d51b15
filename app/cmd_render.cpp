// app/cmd_render.cpp: `pathview render`: headless rendering to EXR or PNG, with a progress bar and a summary.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <mutex>

#include "app/commands.h"
#include "app/progress.h"
#include "app/render_plan.h"
#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/denoise/aov.h"
#include "core/frame/render_output.h"
#include "core/frame/renderer.h"
#include "core/frame/renderer_partial.h"
#include "core/image/image_io.h"
#include "core/image/metrics.h"
#include "core/load/scene_file.h"
#include "core/partial/partial.h"
#include "core/partial/partial_merge.h"
#include "core/render/sky_guide_training.h"
#include "core/scene/environment.h"

namespace pv::app {
namespace {

struct RenderOptions {
    CommonOptions common;
    std::optional<int> spp;
    std::optional<double> seconds;
    std::vector<std::string> outs;  // every -o: the same render written to each
    float exposure = 0.f;
    DisplayOptions display;  // --view-transform and OpenColorIO: PNG outputs
    bool quiet = false;
    std::string samples;  // --samples START:COUNT: a partial render (core/partial/partial.h)
    std::string resume;   // --resume PART.exr: continue a partial render
    std::string shard;    // --shard I/N: shard I of N of --spp's sample indices
    const CLI::App* cmd = nullptr;
    bool aovs = false;              // feature and film-statistics layers in the EXR (core/denoise/aov.h)
    bool denoise = false;           // NFOR (core/denoise/denoise_nfor.h); the raw mean is kept as the noisy.* layer
    std::string denoiser = "nfor";  // or "atrous", the viewer's interactive filter (core/denoise/denoise_atrous.h)
    std::string region;             // --region x0,y0,x1,y1: render only these pixels (core/frame/renderer.h)
};

// The scene overrides given (--environment, --sun ...) as flags, recorded in partial renders so that --resume
// applies them again (exact: %.9g).
std::string scene_flags(const CommonOptions& c) {
    std::string s;
    auto num = [](float v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.9g", v);
        return std::string(buf);
    };
    if (!c.environment.empty()) s += " --environment \"" + c.environment + "\"";
    if (c.env_rotation) s += " --env-rotation " + num(*c.env_rotation);
    if (c.env_strength) s += " --env-strength " + num(*c.env_strength);
    if (c.sun.size() == 3) s += " --sun " + num(c.sun[0]) + "," + num(c.sun[1]) + "," + num(c.sun[2]);
    if (c.sun_irradiance) s += " --sun-irradiance " + num(*c.sun_irradiance);
    if (c.sun_radius) s += " --sun-radius " + num(*c.sun_radius);
    return s.empty() ? s : s.substr(1);
}

// Parses scene_flags() text back into `c`'s scene overrides.
void parse_scene_flags(const std::string& flags, const std::string& what, CommonOptions& c) {
    CommonOptions parsed = c;
    parsed.scene.clear();
    CLI::App parser;
    add_common_options(parser, parsed);
    try {
        parser.parse(flags, false);
    } catch (const CLI::ParseError& e) {
        throw Error(what + ": pathview:scene_flags " + quote_prefix(flags) +
                    " cannot be parsed: " + quote_prefix(e.what()));
    }
    if (!parsed.scene.empty())
        throw Error(what + ": pathview:scene_flags " + quote_prefix(flags) +
                    " holds an argument that is not a flag; expected only --environment, --env-rotation, "
                    "--env-strength, --sun, --sun-irradiance and --sun-radius");
    parsed.scene = c.scene;
    c = parsed;
}

// The progress bar's text: "64 spp  1.2 s".
std::string spp_and_seconds(uint32_t spp, double seconds) {
    char text[64];
    std::snprintf(text, sizeof text, "%u spp  %.1f s", spp, seconds);
    return text;
}

// The request of `o`'s flags (app/render_plan.h).
RenderRequest request_of(const RenderOptions& o) {
    RenderRequest r;
    r.spp = o.spp;
    r.seconds = o.seconds;
    r.samples = o.samples;
    r.resume = o.resume;
    r.shard = o.shard;
    r.region = o.region;
    r.aovs = o.aovs;
    r.denoise = o.denoise;
    r.adaptive = o.common.adaptive;
    r.adaptive_given = o.cmd->get_option("--adaptive")->count() > 0;
    r.scene = o.common.scene;
    for (const std::string& flag : o.common.image_flags)
        if (o.cmd->get_option(flag)->count()) r.image_flags_given.push_back(flag);
    return r;
}

// Refuses, before the render, an output of unknown format or that cannot be written.
void check_outputs(const std::vector<std::string>& outs) {
    for (const std::string& out : outs) {
        const std::string ext = std::filesystem::path(out).extension().string();
        if (ext != ".exr" && ext != ".png" && ext != ".EXR" && ext != ".PNG")
            throw Error(out + ": unknown image format '" + ext + "'; expected .exr or .png");
        check_writable(out);  // before the render, not after it
    }
}

// Loads the scene on a worker thread; on a terminal, shows the elapsed time meanwhile (the OBJ parser reports no
// fraction).
std::shared_ptr<Scene> load_showing_time(const std::string& path, bool tty) {
    const auto start = std::chrono::steady_clock::now();
    auto loading = std::async(std::launch::async, [&path] { return load_scene(path); });
    if (tty)
        while (loading.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready)
            std::fprintf(stderr, "\rpathview: loading %s  %.1f s", path.c_str(),
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    auto scene = std::make_shared<Scene>(loading.get());
    if (tty) std::fprintf(stderr, "\r\033[K");
    return scene;
}

// The renderer of `scene` (the BVH built, its progress drawn on a terminal), with the load and BVH figures.
std::unique_ptr<Renderer> build_renderer(const std::shared_ptr<Scene>& scene, const RenderOptions& o, bool tty,
                                         double load_seconds) {
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
    auto renderer = std::make_unique<Renderer>(scene, o.common.threads,
                                               tty ? std::function<void(double)>(build_progress) : nullptr);
    if (tty) std::fprintf(stderr, "\r\033[K");
    if (!o.quiet) {
        const AccelStats& as = renderer->traceable().accel().stats();
        std::fprintf(stderr, "pathview: loaded %zu triangles in %.2f s; BVH %.2f s, %.1f MiB (%.0f bytes/triangle)\n",
                     scene->triangle_count(), load_seconds, as.build_seconds, double(as.bytes) / (1 << 20),
                     double(as.bytes) / double(std::max<size_t>(1, scene->triangle_count())));
    }
    return renderer;
}

// Restarts the renderer for the plan: adaptive sampling, region, camera and settings, then the resumed part's film
// (refused unless the scene hashes as the part's) and the first sample index.
void start_render(Renderer& renderer, const RenderOptions& o, const RenderPlan& plan, const CameraDesc& camera,
                  const std::optional<PixelRect>& region) {
    renderer.set_adaptive(plan.adaptive);
    renderer.set_region(region);
    renderer.restart(camera, o.common.settings, o.common.width, o.common.height);
    if (plan.resumed) {
        const uint64_t hash = scene_hash(renderer.scene(), renderer.traceable().materials(),
                                         renderer.traceable().environment_settings(), renderer.traceable().fog());
        if (hash != plan.resumed->id.scene_hash)
            throw Error("--resume " + o.resume + ": the scene " + scene_path(o.common) +
                        " (with the part's environment flags) is not "
                        "the one the part was rendered from (scene hash differs)");
        renderer.load_film(plan.resumed->film);
    }
    if (plan.samples) renderer.set_next_sample(uint32_t(plan.samples->start));  // below 2^32: checked by the plan
}

// Renders passes until the plan is done, with a progress bar unless quiet.
void render_passes(Renderer& renderer, const RenderPlan& plan, bool quiet) {
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    ProgressBar bar(!quiet);
    for (;;) {
        const double t = elapsed();
        const RenderStats& st = renderer.stats();
        if (plan.done(st.spp, t, renderer.converged())) break;
        if (bar.enabled())
            bar.draw(plan.spp ? double(st.spp) / *plan.spp : t / *plan.seconds, spp_and_seconds(st.spp, t));
        renderer.render_pass();
    }
    bar.draw(1.0, spp_and_seconds(renderer.stats().spp, elapsed()));
    bar.finish();
}

// The output chain's options from the command line's.
OutputOptions output_options(const RenderOptions& o) {
    OutputOptions out;
    out.aovs = o.aovs;
    out.denoise = o.denoise;
    out.denoiser = o.denoiser == "atrous" ? Denoiser::Atrous : Denoiser::Nfor;
    out.exposure = o.exposure;
    return out;
}

// Writes every -o (a partial render's EXRs as partial files); returns their names, comma-separated.
std::string write_outputs(const RenderOptions& o, const Renderer& renderer, const RenderPlan& plan,
                          const RenderOutput& out, const DisplayTransform& display) {
    std::optional<PartialRender> part;
    if (plan.samples) {
        std::vector<SampleRange> ranges{{plan.samples->start, renderer.stats().spp}};
        if (plan.resumed) ranges.insert(ranges.end(), plan.resumed->ranges.begin(), plan.resumed->ranges.end());
        part = partial_from_renderer(renderer, ranges);
        part->info["pathview:scene_flags"] = scene_flags(o.common);
        if (plan.resumed) add_summed_info(part->info, plan.resumed->info);
    }
    std::string written;
    for (const std::string& file : o.outs) {
        const std::string ext = std::filesystem::path(file).extension().string();
        const bool exr = ext == ".exr" || ext == ".EXR";
        if (part && exr)
            write_partial(file, *part);
        else if (out.layers.size() > 1 && exr)
            write_exr_layers(file, out.image.width, out.image.height, out.layers, out.metadata);
        else
            write_image(file, out.image, out.metadata, display);  // the exposure is in out.image already
        written += (written.empty() ? "" : ", ") + file;
    }
    return written;
}

// The summary lines: the feature pass and denoiser (stderr), then the render's figures, region, sky guide and
// adaptive sampling (stdout).
void print_summary(const RenderOptions& o, const Renderer& renderer, const RenderOutput& out,
                   const std::string& written) {
    if ((o.aovs || o.denoise) && !o.quiet)
        std::fprintf(stderr, "pathview: feature pass (albedo, normal, depth; 8 rays per pixel) %.2f s\n",
                     out.aov_seconds);
    if (o.denoise && !o.quiet)
        std::fprintf(stderr, "pathview: denoised (%s) in %.3f s; the relMSE estimate below is the noisy image's\n",
                     o.denoiser.c_str(), out.nfor.seconds);
    const RenderStats& st = renderer.stats();
    const double secs = std::max(st.seconds, 1e-9);
    if (renderer.settings().max_depth < RenderSettings{}.max_depth)
        std::fprintf(stderr,
                     "pathview: note: --max-depth %d truncates paths, so the image is biased (darker) "
                     "compared with the unbounded default\n",
                     renderer.settings().max_depth);
    std::printf(
        "pathview: %u spp in %.2f s, estimated relMSE %.3g (half buffers), %s paths/s, %s rays/s "
        "(%s closest-hit + %s shadow), %.2f rays/path, %llu dropped samples, %d thread%s, %s -> %s\n",
        st.spp, st.seconds, renderer.film().estimated_rel_mse(), format_si(double(st.paths) / secs).c_str(),
        format_si(double(st.rays + st.shadow_rays) / secs).c_str(), format_si(double(st.rays) / secs).c_str(),
        format_si(double(st.shadow_rays) / secs).c_str(),
        double(st.rays + st.shadow_rays) / double(std::max<uint64_t>(st.paths, 1)),
        static_cast<unsigned long long>(st.dropped), renderer.threads(), renderer.threads() == 1 ? "" : "s",
        renderer.settings_as_rendered().describe().c_str(), written.c_str());
    if (renderer.has_region()) {
        const PixelRect& r = renderer.region();
        std::printf("pathview: region %s: %d x %d pixels rendered, black outside\n", format_region(r).c_str(),
                    r.x1 - r.x0, r.y1 - r.y0);
    }
    if (st.guide_seconds > 0.0) {
        char why[160] = "";
        if (renderer.settings().sky_guide == SkyGuideMode::Auto)
            std::snprintf(why, sizeof why, " (auto: predicted variance x%.2f at x%.2f the time per sample)",
                          st.guide_variance_ratio, kSkyGuideRelativeCost);
        std::printf("pathview: sky guide %s%s, trained in %.3f s (part of the first pass)\n",
                    st.guide_used ? "on" : "off", why, st.guide_seconds);
    }
    // The scene's own lights leave the view dark (no sky or sun lights it): say how to add fill light (issue 41 item
    // 6; the viewer's Light section offers the same in one click). Not for a region: black outside it.
    if (!o.quiet && !renderer.has_region() &&
        !environment_emits(renderer.scene(), renderer.traceable().environment_settings())) {
        const Image mean = renderer.film().mean();
        const double y = mean_display_luminance(mean.rgb.data(), size_t(mean.width) * size_t(mean.height));
        if (y < kDarkMeanLuminance)
            std::fprintf(
                stderr,
                "pathview: hint: the image is dark (mean displayed luminance %.2g): the scene's own lights barely "
                "reach this view; --environment sky adds the default sky, --environment 0.5 a neutral grey "
                "fill\n",
                y);
    }
    const AdaptiveSettings& adaptive = renderer.adaptive_settings();
    if (adaptive.allocate && !adaptive.enabled())
        std::printf("pathview: adaptive sampling: %.1f samples per pixel on average (%u passes)\n",
                    renderer.film().mean_count(), st.spp);
    if (adaptive.enabled())
        std::printf(
            "pathview: noise threshold %g: %.1f%% of pixels still active, %.1f samples per pixel on average%s\n",
            double(adaptive.noise_threshold), 100.0 * renderer.adaptive_mask().active_fraction(),
            double(st.paths) / double(std::max(1, o.common.width * o.common.height)),
            renderer.converged() ? " (every pixel converged)" : "");
}

void run(RenderOptions& o) {
    resolve_switches(o.common);
    // The plan (app/render_plan.h): sample counts, partial render, resumed part; a part's scene flags apply
    // as soon as it is read.
    const RenderPlan plan = plan_render(request_of(o), [&](const PartialRender& part) {
        const auto flags = part.info.find("pathview:scene_flags");
        parse_scene_flags(flags == part.info.end() ? "" : flags->second, o.resume, o.common);
    });
    o.common.scene = plan.scene;
    check_outputs(o.outs);
    check_film_memory(o.common.width, o.common.height);
    const DisplayTransform display = resolve_display(o.display, ViewTransform::Clamp);  // before the render
    std::optional<PixelRect> region;
    if (!o.region.empty()) region = parse_region(o.region, o.common.width, o.common.height, "--region");

    const bool tty = !o.quiet && isatty(STDERR_FILENO);
    const auto load_start = std::chrono::steady_clock::now();
    const std::shared_ptr<Scene> scene = load_showing_time(scene_path(o.common), tty);
    CameraDesc camera = set_up_scene(o.common, *scene);
    const double load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count();
    if (plan.resumed) {
        camera = parse_camera(plan.resumed->id.camera, o.resume);
        o.common.settings = parse_settings(plan.resumed->id.settings, o.resume);
        o.common.width = plan.resumed->id.width;
        o.common.height = plan.resumed->id.height;
    }
    const std::unique_ptr<Renderer> renderer = build_renderer(scene, o, tty, load_seconds);
    start_render(*renderer, o, plan, camera, region);
    render_passes(*renderer, plan, o.quiet);
    const RenderOutput out = finish_render(*renderer, output_options(o));
    print_summary(o, *renderer, out, write_outputs(o, *renderer, plan, out, display));
}

}  // namespace

void add_render_command(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render",
                                       "Render a scene headless to an OpenEXR (linear FLOAT RGB + metadata) "
                                       "or PNG (through --view-transform) file");
    add_common_options(*cmd, o->common);
    auto* spp = cmd->add_option("--spp", o->spp, "Samples per pixel (default 64 when --time is not given)")
                    ->check(CLI::Range(1, 1 << 30));
    cmd->add_option("--time", o->seconds, "Render for this many seconds (whole passes)")
        ->check(finite_range(0, 1e9))
        ->excludes(spp);
    cmd->add_option("-o,--output", o->outs, "Output file: .exr or .png; repeat -o to write several")
        ->required()
        ->take_all();
    add_exposure_option(*cmd, o->exposure, "Exposure in stops applied before writing");
    add_display_options(*cmd, o->display, "clamp");
    cmd->add_flag("-q,--quiet", o->quiet, "No progress bar");
    auto* samples = cmd->add_option("--samples", o->samples,
                                    "Render only the sample indices START..START+COUNT-1 (START:COUNT; with --time, "
                                    "at most COUNT, as many as fit) and write a partial render that `pathview merge` "
                                    "combines with the other ranges (EXR outputs: R G B = this range's image, plus "
                                    "the exact per-pixel sums)")
                        ->excludes(spp);
    auto* resume =
        cmd->add_option("--resume", o->resume,
                        "Continue the partial render PART.exr (from `--samples` or `pathview merge`) with --spp N more "
                        "samples after its last index; scene, camera, size and settings come from the part")
            ->excludes(samples);
    cmd->add_option("--shard", o->shard,
                    "Render shard I of N (I/N, I from 0) of the --spp sample indices as a partial render, like "
                    "--samples with the range computed: N contiguous ranges that tile [0, spp)")
        ->needs(spp)
        ->excludes(samples)
        ->excludes(resume);
    o->cmd = cmd;
    cmd->add_flag("--aovs", o->aovs,
                  "EXR outputs also hold first-hit albedo (Albedo.*), shading normal (Ns.*), "
                  "depth (Z), SampleCount, Variance.* (of the mean) and the even/odd half means (even.*, odd.*); "
                  "see core/denoise/aov.h");
    cmd->add_flag("--denoise", o->denoise,
                  "Denoise (NFOR regression on first-hit features, cross-validated between "
                  "the even/odd halves): the image written is denoised, EXRs keep the raw mean as noisy.R/G/B");
    cmd->add_option("--region", o->region,
                    "Render only the pixels x0 <= x < x1, y0 <= y < y1 (x0,y0,x1,y1 from the top-left): each takes "
                    "the samples a full render gives it, the rest of the image is black; EXR metadata "
                    "pathview:region. Not with partial renders, --denoise or adaptive sampling");
    cmd->add_option("--denoiser", o->denoiser,
                    "Denoiser for --denoise: nfor (final quality) or atrous (the viewer's "
                    "interactive edge-avoiding filter)")
        ->check(CLI::IsMember({"nfor", "atrous"}))
        ->capture_default_str();
    cmd->callback([o] { run(*o); });
}

}  // namespace pv::app
