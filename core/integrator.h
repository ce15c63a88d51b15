// core/integrator.h: the path tracer. Solves the rendering equation by Monte Carlo with BSDF importance
// sampling, optional next-event estimation (light sampling) combined with BSDF sampling by MIS (power heuristic),
// optional Russian roulette and a depth cap. Every switch combination converges to the same image, except that
// max_depth truncates paths. max_depth counts scattering events: 0 shows only emitters seen directly.
#pragma once

#include <cstdint>
#include <string>

#include "core/sampler.h"
#include "core/traceable_scene.h"

namespace pv {

// --sky-guide: off, on, or auto (trained, then used where the training predicts it pays; core/sky_guide.h).
enum class SkyGuideMode : uint8_t { Off, On, Auto };

// The estimator's switches, as plain data. Defaults are unbiased in practice (depth 1024 is never reached
// with roulette on: survival falls geometrically with throughput).
struct RenderSettings {
    bool light_sampling = true;  // next-event estimation over emissive triangles, sky and sun
    bool mis = true;             // power-heuristic MIS between light and BSDF sampling (needs light_sampling)
    bool russian_roulette = true;
    int max_depth = 1024;
    uint32_t seed = 0;
    // Owen-scrambled Sobol: measured better at equal time on the Cornell box (BENCHMARKS.md sections 1 and 5).
    SamplerKind sampler = SamplerKind::Sobol;  // see core/sampler.h
    // Next-event estimation of the sky guided toward the directions a training pre-pass found unoccluded
    // (core/sky_guide.h); only where the sky shines and the scene has no portals. Auto by default: the training
    // predicts whether the guide pays for its cost (it halves the error of a room lit by the sky through a window,
    // and costs more than it gains on the sun-lit room, Sibenik and the conference room; docs/sky-guide.md).
    SkyGuideMode sky_guide = SkyGuideMode::Auto;

    bool operator==(const RenderSettings& o) const {
        return light_sampling == o.light_sampling && mis == o.mis && russian_roulette == o.russian_roulette &&
               max_depth == o.max_depth && seed == o.seed && sampler == o.sampler && sky_guide == o.sky_guide;
    }
    bool operator!=(const RenderSettings& o) const { return !(*this == o); }
    // One line for logs and EXR metadata, e.g. "nee=on mis=on rr=on max_depth=1024 seed=0 sampler=independent",
    // then " sky_guide=on" or " sky_guide=auto" (strings from before the guide existed mean it off; a render's
    // settings_as_rendered() resolves auto to on or off).
    std::string describe() const;
};

// Per-thread counters, added to the renderer's totals once per tile.
struct PathCounters {
    uint64_t rays = 0;         // closest-hit rays
    uint64_t shadow_rays = 0;  // occlusion rays
    uint64_t paths = 0;
    uint64_t vertices = 0;  // surface interactions
};

// Sampler dimensions: a sample's camera ray uses dimensions 0 (film position) and 1 (lens), then each bounce a
// block of kBounceDims (light selection, light point, BSDF lobe, BSDF direction, roulette). A dimension keeps its
// meaning in every sample of a pixel; a draw that a vertex does not need is skipped, not shifted.
constexpr uint32_t kCameraDims = 2;
constexpr uint32_t kBounceDims = 5;

// Russian roulette spares paths whose throughput max(beta) x eta^2 is at least this (the roulette block in
// trace_path; every path walker that plays roulette, such as the sky guide's training, uses the same rule).
constexpr float kRouletteThroughput = 0.5f;

// Starts sample `index` of pixel (x, y) and returns its camera ray: the film point jittered uniformly over the
// pixel (a box filter; its centre with pixel_centre) and, for a thin lens, the lens point. Every renderer (and test)
// draws camera rays through this one function.
inline Ray camera_ray(const Camera& camera, Sampler& sampler, int x, int y, uint32_t index, bool pixel_centre = false) {
    sampler.start(uvec2(uint32_t(x), uint32_t(y)), index);
    const uint32_t dim = sampler.reserve(kCameraDims);
    const vec2 film = vec2(float(x), float(y)) + (pixel_centre ? vec2(0.5f) : sampler.get2d_at(dim));
    return camera.generate(film, camera.has_lens() ? sampler.get2d_at(dim + 1) : vec2(0.5f));
}

// Radiance arriving along `ray` in `scene` (shared read-only by all threads). Uses kBounceDims sampler dimensions
// per bounce.
vec3 trace_path(const TraceableScene& ts, const RenderSettings& settings, Ray ray, Sampler& sampler,
                PathCounters& counters);

}  // namespace pv
