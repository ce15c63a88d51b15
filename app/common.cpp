// app/common.cpp: options shared by the subcommands that render.
#include "app/commands.h"

#include "core/error.h"
#include "core/scene_file.h"

#include <algorithm>

namespace pv::app {
namespace {

bool parse_switch(const std::string& name, const std::string& value) {
    if (value == "on") return true;
    if (value == "off") return false;
    throw Error("--" + name + " " + value + ": expected on or off");
}

vec3 to_vec3(const std::vector<float>& v) { return vec3(v[0], v[1], v[2]); }

}  // namespace

void add_common_options(CLI::App& cmd, CommonOptions& o) {
    cmd.add_option("scene", o.scene, "Scene: a .json scene file or an .obj (default: the built-in Cornell box)");
    cmd.add_option("--width", o.width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
    cmd.add_option("--height", o.height, "Image height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
    cmd.add_option("--threads", o.threads, "Render threads (0: all cores)")->check(CLI::Range(0, 1024))->capture_default_str();
    cmd.add_option("--seed", o.settings.seed, "Random seed (the image depends only on it, not on threads)")
        ->capture_default_str();
    cmd.add_option("--max-depth", o.settings.max_depth,
                   "Maximum number of scattering events (0: emitters seen directly only)")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    cmd.add_option("--light-sampling", o.light_sampling, "Next-event estimation: on|off")->capture_default_str();
    cmd.add_option("--mis", o.mis, "Multiple importance sampling of light and BSDF samples: on|off")->capture_default_str();
    cmd.add_option("--rr", o.rr, "Russian roulette: on|off")->capture_default_str();
    cmd.add_option("--sampler", o.sampler, "Sample generator: independent|sobol (Owen-scrambled, padded)")
        ->capture_default_str();
    cmd.add_option("--noise-threshold", o.adaptive.noise_threshold,
                   "Adaptive sampling: a pixel whose relative error (from the two half buffers, averaged over 5x5 "
                   "pixels) is below this stops taking samples, e.g. 0.02; 0: off")
        ->check(CLI::Range(0.f, 1.f));
    cmd.add_option("--min-spp", o.adaptive.min_spp, "Adaptive sampling: samples every pixel takes before it may stop")
        ->check(CLI::Range(2u, 1u << 30))
        ->capture_default_str();
    cmd.add_option("--eye", o.eye, "Camera position x,y,z")->expected(3)->delimiter(',');
    cmd.add_option("--target", o.target, "Camera target x,y,z")->expected(3)->delimiter(',');
    cmd.add_option("--up", o.up, "Camera up vector x,y,z")->expected(3)->delimiter(',');
    cmd.add_option("--fov", o.fov, "Vertical field of view, degrees")->check(CLI::Range(0.01f, 179.f));
    cmd.add_option("--aperture", o.aperture, "Thin-lens radius in scene units (0: pinhole)")->check(CLI::Range(0.f, 1e30f));
    cmd.add_option("--focus-distance", o.focus_distance, "Focus distance in scene units (0: at the target)")
        ->check(CLI::Range(0.f, 1e30f));
    cmd.add_option("--bookmark", o.bookmark, "Start from the camera bookmark of this name saved in the scene file");
    cmd.add_option("--environment", o.environment,
                   "Light from far away: r,g,b or one number (constant radiance), 'sky' (the default sky), or an "
                   "equirectangular map (.exr, .hdr, .png)");
    cmd.add_option("--env-rotation", o.env_rotation, "Environment rotation about +y, degrees");
    cmd.add_option("--env-strength", o.env_strength, "Environment radiance multiplier")->check(CLI::Range(0.f, 1e30f));
    cmd.add_option("--sun", o.sun, "Add a sun in direction x,y,z (toward the sun)")->expected(3)->delimiter(',');
    cmd.add_option("--sun-irradiance", o.sun_irradiance, "Sun irradiance on a surface facing it (default 5 with --sun)")
        ->check(CLI::Range(0.f, 1e30f));
    cmd.add_option("--sun-radius", o.sun_radius, "Sun angular radius, degrees (default 0.27)")->check(CLI::Range(0.01f, 45.f));
}

void resolve_switches(CommonOptions& o) {
    o.settings.light_sampling = parse_switch("light-sampling", o.light_sampling);
    o.settings.mis = parse_switch("mis", o.mis);
    o.settings.russian_roulette = parse_switch("rr", o.rr);
    const auto kind = parse_sampler(o.sampler);
    if (!kind) throw Error("--sampler " + o.sampler + ": expected independent or sobol");
    o.settings.sampler = *kind;
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
        set_environment(scene, o.environment);
        // The default-sky notice no longer applies.
        if (scene.default_sky_warning && *scene.default_sky_warning < scene.warnings.size())
            scene.warnings.erase(scene.warnings.begin() + std::ptrdiff_t(*scene.default_sky_warning));
        scene.default_sky_warning.reset();
    }
    if (o.env_rotation) scene.environment_rotation_deg = *o.env_rotation;
    if (o.env_strength) scene.environment_strength = *o.env_strength;
    if (o.sun.size() == 3) {
        scene.sun_direction = vec3(o.sun[0], o.sun[1], o.sun[2]);
        if (!(glm::length(scene.sun_direction) > 0.f)) throw Error("--sun: the direction must not be zero");
        scene.sun_irradiance = vec3(o.sun_irradiance.value_or(5.f));
    } else if (o.sun_irradiance) {
        scene.sun_irradiance = vec3(*o.sun_irradiance);
    }
    if (o.sun_radius) scene.sun_angular_radius_deg = *o.sun_radius;
}

std::string scene_path(const CommonOptions& o) { return o.scene.empty() ? builtin_scene_path() : o.scene; }

}  // namespace pv::app
