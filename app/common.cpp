// app/common.cpp: options shared by the subcommands that render.
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>

#include "app/commands.h"
#include "core/base/error.h"
#include "core/base/parallel.h"
#include "core/image/film.h"
#include "core/image/image_io.h"
#include "core/load/scene_file.h"
#include "core/scene/environment.h"

namespace pv::app {
namespace {

// A CLI11 transformer from words to the option's values (as the text CLI11 then converts: "1"/"0" for a bool, the
// integer of an enum), so a switch binds straight to its setting; any other word is refused listing the choices.
CLI::Validator choices(std::vector<std::pair<std::string, int>> words) {
    std::string names;
    for (const auto& [w, v] : words) names += (names.empty() ? "" : "|") + w;
    return CLI::Validator(
        [words, names](std::string& s) -> std::string {
            for (const auto& [w, v] : words)
                if (s == w) {
                    s = std::to_string(v);
                    return {};
                }
            return "'" + s + "': expected " + names;
        },
        names);
}

// The words of a table (core/base/text.h) as a choices() transformer.
template <class T, size_t N>
CLI::Validator choices(const NamedValue<T> (&table)[N]) {
    std::vector<std::pair<std::string, int>> words;
    for (const NamedValue<T>& e : table) words.emplace_back(e.name, int(e.value));
    return choices(std::move(words));
}

const CLI::Validator kOnOff = choices(kOnOffNames);
std::string on_off(bool b) { return name_of(kOnOffNames, b); }

// Every field of RenderSettings as its option (core/render/settings.h): words through choices(), numbers checked
// against their range.
void add_setting_options(CLI::App& cmd, RenderSettings& settings) {
    for_each_setting([&](const auto& f) {
        using T = std::decay_t<decltype(settings.*f.member)>;
        CLI::Option* opt = cmd.add_option(f.flag, settings.*f.member, f.help);
        if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
            if (f.ranged) opt->check(CLI::Range(f.lo, f.hi));
            opt->capture_default_str();
        } else {
            std::vector<std::pair<std::string, int>> words;
            for (size_t i = 0; i < f.name_count; ++i) words.emplace_back(f.names[i].name, int(f.names[i].value));
            opt->transform(choices(std::move(words)))->default_str(f.name(settings.*f.member));
        }
    });
}

// "r,g,b" or one number, as a colour; nothing when `s` is not such a list (then it names a map or "sky").
std::optional<vec3> parse_colour(const std::string& s) {
    std::vector<float> values;
    for (size_t pos = 0; pos <= s.size();) {
        const size_t comma = std::min(s.find(',', pos), s.size());
        const std::string part = s.substr(pos, comma - pos);
        char* end = nullptr;
        const float v = std::strtof(part.c_str(), &end);
        if (part.empty() || end != part.c_str() + part.size()) return std::nullopt;
        values.push_back(v);
        pos = comma + 1;
    }
    if (values.size() == 1) return vec3(values[0]);
    if (values.size() == 3) return vec3(values[0], values[1], values[2]);
    return std::nullopt;
}

vec3 to_vec3(const std::vector<float>& v) { return vec3(v[0], v[1], v[2]); }

// Bytes of memory this process can still get: MemAvailable, or less under a cgroup (v2) limit; 0 if unknown.
uint64_t available_memory() {
    uint64_t avail = 0;
    if (std::FILE* f = std::fopen("/proc/meminfo", "r")) {
        char line[256];
        unsigned long long kb = 0;
        while (std::fgets(line, sizeof line, f))
            if (std::sscanf(line, "MemAvailable: %llu kB", &kb) == 1) avail = uint64_t(kb) * 1024;
        std::fclose(f);
    }
    unsigned long long max = 0, cur = 0;
    std::FILE* fm = std::fopen("/sys/fs/cgroup/memory.max", "r");
    std::FILE* fc = std::fopen("/sys/fs/cgroup/memory.current", "r");
    if (fm && fc && std::fscanf(fm, "%llu", &max) == 1 && std::fscanf(fc, "%llu", &cur) == 1 && max > cur)
        avail = avail ? std::min<uint64_t>(avail, max - cur) : max - cur;
    if (fm) std::fclose(fm);
    if (fc) std::fclose(fc);
    struct rlimit as {};
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
        avail = avail ? std::min<uint64_t>(avail, uint64_t(as.rlim_cur)) : uint64_t(as.rlim_cur);
    return avail;
}

}  // namespace

CLI::Validator finite_range(double lo, double hi) {
    char desc[96];
    std::snprintf(desc, sizeof desc, "FINITE in [%g - %g]", lo, hi);
    return CLI::Validator(
        [lo, hi](std::string& s) -> std::string {
            // CLI::Range lets NaN through (every comparison with NaN is false) and accepts inf.
            double v = 0;
            if (!CLI::detail::lexical_cast(s, v)) return "'" + s + "' is not a number";
            if (!std::isfinite(v) || v < lo || v > hi) {
                char msg[128];
                std::snprintf(msg, sizeof msg, "%s is not a finite number in [%g, %g]", s.c_str(), lo, hi);
                return msg;
            }
            return {};
        },
        desc);
}

namespace {
// When per_pixel x width x height bytes exceed the memory available: "about X GB<purpose> (Y bytes a pixel) but Z GB
// of memory are available"; else empty.
std::string memory_shortfall(double per_pixel, int width, int height, const char* purpose = "") {
    const double need = per_pixel * double(width) * double(height);
    const uint64_t avail = available_memory();
    if (!avail || need <= double(avail)) return {};
    char msg[160];
    std::snprintf(msg, sizeof msg, "about %.1f GB%s (%.0f bytes a pixel) but %.1f GB of memory are available",
                  need * 1e-9, purpose, per_pixel, double(avail) * 1e-9);
    return msg;
}
}  // namespace

void check_film_memory(int width, int height) {
    // Per pixel: the film (sums in double) and the float image written at the end.
    const std::string s = memory_shortfall(double(sizeof(FilmPixel) + 3 * sizeof(float)), width, height);
    if (!s.empty())
        throw Error("--width " + std::to_string(width) + " --height " + std::to_string(height) + ": the film needs " +
                    s + "; render a smaller image");
}

void check_merge_memory(const std::string& part, int width, int height) {
    // The output film, the float mean and, for a PNG, its bytes; a block of a part is small beside them.
    const std::string s =
        memory_shortfall(double(sizeof(FilmPixel) + 3 * sizeof(float) + 3), width, height, " to merge");
    if (!s.empty())
        throw Error(part + ": " + std::to_string(width) + "x" + std::to_string(height) + " parts need " + s);
}

CLI::Option* add_exposure_option(CLI::App& cmd, float& stops, const std::string& help) {
    return cmd.add_option("--exposure", stops, help)->check(finite_range(-64, 64))->capture_default_str();
}

void add_display_options(CLI::App& cmd, DisplayOptions& o, const char* default_transform) {
    cmd.add_option("--view-transform", o.view_transform,
                   "How linear radiance becomes display values in PNG files and on screen (EXR stays linear): "
                   "clamp (sRGB), reinhard, aces (Narkowicz's fit), agx (Blender 4's), pbr-neutral (Khronos), or "
                   "ocio (an OpenColorIO display/view)")
        ->check(CLI::IsMember(std::vector<std::string>{"clamp", "reinhard", "aces", "agx", "pbr-neutral", "ocio"}))
        ->default_str(default_transform);
    cmd.add_option("--ocio-config", o.ocio_config,
                   "OpenColorIO config file for --view-transform ocio (default: $OCIO); implies ocio");
    cmd.add_option("--ocio-display", o.ocio_display,
                   "OpenColorIO display (default: the config's); implies --view-transform ocio");
    cmd.add_option("--ocio-view", o.ocio_view,
                   "OpenColorIO view of that display (default: the display's); implies --view-transform ocio");
    cmd.add_option("--ocio-input", o.ocio_input,
                   "The config's colour space (or role) for pathview's linear Rec.709 RGB; implies --view-transform "
                   "ocio")
        ->capture_default_str();
}

DisplayTransform resolve_display(const DisplayOptions& o, ViewTransform fallback, bool offers_config) {
    const bool picks_view = !o.ocio_display.empty() || !o.ocio_view.empty();
    const bool names_config = !o.ocio_config.empty() || o.ocio_input != "scene_linear";
    DisplayTransform t;
    t.transform = fallback;
    if (!o.view_transform.empty()) {
        t.transform = *value_of(kViewTransformNames, o.view_transform);  // CLI11 checked the word
        if (t.transform != ViewTransform::Ocio && (picks_view || (names_config && !offers_config)))
            throw Error("--view-transform " + o.view_transform + ": " +
                        (offers_config ? "--ocio-display and --ocio-view apply"
                                       : "--ocio-config, --ocio-display, --ocio-view and --ocio-input apply") +
                        " to --view-transform ocio only");
    } else if (picks_view || names_config) {
        t.transform = ViewTransform::Ocio;
    }
    if (t.transform == ViewTransform::Ocio)
        t.ocio = std::make_shared<const OcioView>(OcioConfig::load(o.ocio_config), o.ocio_display, o.ocio_view,
                                                  o.ocio_input);
    return t;
}

std::shared_ptr<const OcioConfig> offered_ocio_config(const DisplayOptions& o, const DisplayTransform& chosen) {
    if (chosen.ocio) return std::shared_ptr<const OcioConfig>(chosen.ocio, &chosen.ocio->config());
    if (!o.ocio_config.empty()) return OcioConfig::load(o.ocio_config);
    const char* env = std::getenv("OCIO");
    if (!env || !*env) return nullptr;
    try {
        return OcioConfig::load("");
    } catch (const Error& e) {
        std::fprintf(stderr, "pathview: note: $OCIO: %s; OpenColorIO is not offered\n", e.what());
        return nullptr;
    }
}

CLI::Option* add_image_budget_option(CLI::App& cmd, double& megapixels, const std::string& help) {
    return cmd.add_option("--max-image-megapixels", megapixels, help)
        ->check(finite_range(0.001, 1e6))
        ->capture_default_str();
}

void add_common_options(CLI::App& cmd, CommonOptions& o) {
    // An option that defines the image (size, settings, camera, scene overrides): --resume takes it from the part.
    o.image_flags.clear();
    auto image = [&](CLI::Option* opt) {
        o.image_flags.push_back("--" + opt->get_lnames().front());
        return opt;
    };
    cmd.add_option("scene", o.scene,
                   "Scene: a .json scene file, an .obj, a .gltf or a .glb (default: the built-in Cornell box)");
    image(cmd.add_option("--width", o.width, "Image width in pixels")
              ->check(CLI::Range(1, 16384))
              ->capture_default_str());
    image(cmd.add_option("--height", o.height, "Image height in pixels")
              ->check(CLI::Range(1, 16384))
              ->capture_default_str());
    cmd.add_option("--threads", o.threads, "Render threads (0: every core this process may use; at most that many)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    add_setting_options(cmd, o.settings);
    for_each_setting([&](const auto& f) { o.image_flags.push_back(f.flag); });
    cmd.add_option("--adaptive", o.adaptive.allocate,
                   "Adaptive sampling: each region takes samples in proportion to its relative error per sample, "
                   "estimated from pilot passes that never steer their own samples (unbiased; --spp counts the "
                   "passes, which the noisiest pixels all take; not with partial renders): on|off")
        ->transform(kOnOff)
        ->default_str(on_off(o.adaptive.allocate));
    cmd.add_option("--noise-threshold", o.adaptive.noise_threshold,
                   "Adaptive sampling: a pixel whose relative error (from the two half buffers, averaged over 5x5 "
                   "pixels) is below this stops taking samples, e.g. 0.02; 0: off")
        ->check(finite_range(0, 1));
    cmd.add_option("--min-spp", o.adaptive.min_spp, "Adaptive sampling: samples every pixel takes before it may stop")
        ->check(CLI::Range(2u, 1u << 30))
        ->capture_default_str();
    image(cmd.add_option("--eye", o.eye, "Camera position x,y,z")
              ->expected(3)
              ->delimiter(',')
              ->check(finite_range(-1e30, 1e30)));
    image(cmd.add_option("--target", o.target, "Camera target x,y,z")
              ->expected(3)
              ->delimiter(',')
              ->check(finite_range(-1e30, 1e30)));
    image(cmd.add_option("--up", o.up, "Camera up vector x,y,z")
              ->expected(3)
              ->delimiter(',')
              ->check(finite_range(-1e30, 1e30)));
    image(cmd.add_option("--fov", o.fov, "Vertical field of view, degrees")->check(finite_range(0.01, 179)));
    image(cmd.add_option("--aperture", o.aperture, "Thin-lens radius in scene units (0: pinhole)")
              ->check(finite_range(0, 1e30)));
    image(cmd.add_option("--focus-distance", o.focus_distance, "Focus distance in scene units (0: at the target)")
              ->check(finite_range(0, 1e30)));
    image(cmd.add_option("--bookmark", o.bookmark,
                         "Start from the camera bookmark of this name saved in the scene file"));
    image(cmd.add_option("--environment", o.environment,
                         "Light from far away: r,g,b or one number (constant radiance), 'sky' (the default sky), or an "
                         "equirectangular map (.exr, .hdr, .png)"));
    image(cmd.add_option("--env-rotation", o.env_rotation, "Environment rotation about +y, degrees")
              ->check(finite_range(-1e30, 1e30)));
    image(cmd.add_option("--env-strength", o.env_strength, "Environment radiance multiplier")
              ->check(finite_range(0, 1e30)));
    image(cmd.add_option("--sun", o.sun, "Add a sun in direction x,y,z (toward the sun)")
              ->expected(3)
              ->delimiter(',')
              ->check(finite_range(-1e30, 1e30)));
    image(cmd.add_option("--sun-irradiance", o.sun_irradiance,
                         "Sun irradiance on a surface facing it (default 5 with --sun)")
              ->check(finite_range(0, 1e30)));
    image(cmd.add_option("--fog", o.fog,
                         "Fill the scene with a homogeneous medium (the camera inside it, closed glass solids "
                         "excluded): SIGMA_S[,SIGMA_A[,G]], scattering and absorption per scene unit, the "
                         "Henyey-Greenstein g in [-0.99, 0.99] (default 0); --fog 0 removes the scene file's fog")
              ->expected(1, 3)
              ->delimiter(',')
              ->check(finite_range(-1e30, 1e30)));
    add_image_budget_option(cmd, o.max_image_megapixels,
                            "Largest environment map or texture read, in megapixels (a 16384x8192 map is 134); larger "
                            "or implausibly small files are refused before decoding");
    image(cmd.add_option("--sun-radius", o.sun_radius, "Sun angular radius, degrees (default 0.27)")
              ->check(finite_range(kSunRadiusMinDeg, kSunRadiusMaxDeg)));
}

void resolve_switches(CommonOptions& o) {
    // TBB runs at most as many threads as the cores this process may use, whatever the arena asks for: report that.
    const int usable = usable_cores();
    if (o.threads > usable) {
        std::fprintf(stderr, "pathview: note: --threads %d: %d cores can be used here; rendering with %d threads\n",
                     o.threads, usable, usable);
        o.threads = usable;
    }
    set_image_limits(ImageLimits{uint64_t(o.max_image_megapixels * 1e6)});
}

void apply_camera_overrides(const CommonOptions& o, const Scene& scene, CameraDesc& c) {
    if (!o.bookmark.empty()) c = find_bookmark(scene, o.bookmark);
    if (o.eye.size() == 3) c.eye = to_vec3(o.eye);
    if (o.target.size() == 3) c.target = to_vec3(o.target);
    if (o.up.size() == 3) c.up = to_vec3(o.up);
    if (o.fov) c.vfov_deg = *o.fov;
    if (o.aperture) c.aperture = *o.aperture;
    if (o.focus_distance) c.focus_distance = *o.focus_distance;
}

void apply_scene_overrides(const CommonOptions& o, Scene& scene) {
    if (!o.environment.empty()) {
        if (const std::optional<vec3> colour = parse_colour(o.environment)) {
            if (!is_finite(*colour) || glm::any(glm::lessThan(*colour, vec3(0.f))))
                throw Error("--environment " + o.environment + ": a colour must be finite and non-negative");
            scene.environment.background = *colour;
            scene.environment_map = kNoIndex;
        } else {
            set_environment_map(scene, o.environment);
        }
        // The default-sky notice no longer applies.
        if (scene.default_sky_warning && *scene.default_sky_warning < scene.warnings.size())
            scene.warnings.erase(scene.warnings.begin() + std::ptrdiff_t(*scene.default_sky_warning));
        scene.default_sky_warning.reset();
    }
    if (o.env_rotation) scene.environment.rotation_deg = *o.env_rotation;
    if (o.env_strength) scene.environment.strength = *o.env_strength;
    if (o.sun.size() == 3) {
        scene.environment.sun_direction = vec3(o.sun[0], o.sun[1], o.sun[2]);
        if (!(glm::length(scene.environment.sun_direction) > 0.f)) throw Error("--sun: the direction must not be zero");
        scene.environment.sun_irradiance = vec3(o.sun_irradiance.value_or(5.f));
    } else if (o.sun_irradiance) {
        scene.environment.sun_irradiance = vec3(*o.sun_irradiance);
    }
    if (o.sun_radius) scene.environment.sun_angular_radius_deg = *o.sun_radius;
    if (!o.fog.empty()) {
        HomogeneousMedium fog;
        fog.sigma_s = vec3(o.fog[0]);
        if (o.fog.size() > 1) fog.sigma_a = vec3(o.fog[1]);
        if (o.fog.size() > 2) fog.g = o.fog[2];
        if (o.fog[0] < 0.f || (o.fog.size() > 1 && o.fog[1] < 0.f))
            throw Error("--fog: SIGMA_S and SIGMA_A must not be negative");
        if (!(std::fabs(fog.g) <= kMaxMediumG)) throw Error("--fog: G must be in [-0.99, 0.99]");
        scene.fog = fog;
    }
}

CameraDesc set_up_scene(const CommonOptions& o, Scene& scene) {
    apply_scene_overrides(o, scene);
    for (const std::string& w : scene.warnings) std::fprintf(stderr, "pathview: warning: %s\n", w.c_str());
    CameraDesc camera = scene.camera;
    apply_camera_overrides(o, scene, camera);
    return camera;
}

std::string scene_path(const CommonOptions& o) { return o.scene.empty() ? builtin_scene_path() : o.scene; }

}  // namespace pv::app
