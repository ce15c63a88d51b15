// core/render/integrator.h: the path tracer. Solves the rendering equation by Monte Carlo with BSDF importance
// sampling, optional next-event estimation (light sampling) combined with BSDF sampling by MIS (power heuristic),
// optional Russian roulette and a depth cap. Every switch combination converges to the same image, except that
// max_depth truncates paths. max_depth counts scattering events: 0 shows only emitters seen directly.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "core/render/light_groups.h"
#include "core/render/settings.h"
#include "core/render/shading.h"
#include "core/render/surface.h"
#include "core/render/traceable_scene.h"
#include "core/sampling/sampler.h"

namespace pv {

// Per-thread counters, added to the renderer's totals once per tile.
struct PathCounters {
    uint64_t rays = 0;         // closest-hit rays
    uint64_t shadow_rays = 0;  // occlusion rays
    uint64_t paths = 0;
    uint64_t vertices = 0;  // surface interactions
    PathCounters& operator+=(const PathCounters& o) {
        rays += o.rays;
        shadow_rays += o.shadow_rays;
        paths += o.paths;
        vertices += o.vertices;
        return *this;
    }
};

// Sampler dimensions: a sample's camera ray uses dimensions 0 (film position) and 1 (lens), then each bounce a
// block of kBounceDims (light selection, light point, BSDF lobe, BSDF direction, roulette). A dimension keeps its
// meaning in every sample of a pixel; a draw that a vertex does not need is skipped, not shifted.
constexpr uint32_t kCameraDims = 2;
constexpr uint32_t kBounceDims = 5;
// Each segment through a medium (the fog, or a material's interior medium) first draws kMediumDims (distance
// channel, distance, and the equiangular distance toward point and spot lights); a scattering event in the medium then
// takes a bounce block like a surface vertex (light selection, light point, unused, phase direction, roulette).
// Segments outside media draw none.
constexpr uint32_t kMediumDims = 3;
// How many closed transmissive solids a path can be inside at once (the walker's medium stack, docs/media.md).
constexpr int kMaxMediumNesting = 4;

// Russian roulette spares paths whose throughput max(beta) x eta^2 is at least this (PathWalker::roulette; the sky
// guide's training walks its paths with a PathWalker).
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

// A vertex of a PathWalker's path that takes a light sample (its BSDF is not a delta one), as an observer sees it:
// the surface point, the geometric and shading frames, the outgoing direction in the shading frame, the BSDF with the
// hit's textures applied, and the path's throughput up to it.
struct PathVertex {
    const SurfacePoint& sf;
    vec3 ng;  // the geometric normal facing wo (shading_normals)
    const Frame& frame;
    vec3 wo;
    const Bsdf& bsdf;
    vec3 beta;
};

// Watches a PathWalker's path without changing it (the sky guide's training, core/render/sky_guide_training.h, walks
// its paths with one): vertex() at each vertex that takes a light sample, before it does; light() for each light
// sample of next-event estimation found unoccluded, with its draws and the radiance it adds to the path (before MIS
// weights: the walker's settings decide them).
class PathObserver {
public:
    virtual void vertex(const PathVertex& v) = 0;
    virtual void light(const LightSample& ls, float u_select, vec2 u_light, vec3 added) = 0;

protected:
    ~PathObserver() = default;
};

// One path, advanced a stage at a time (pbrt-v4's PathIntegrator::Li cut at its two waits for memory). step() runs
// until the path must wait for data it has just prefetched, the hit triangle's record after a closest hit and the
// texels under a textured hit, and returns; the caller can then advance other paths while the loads arrive
// (Renderer::render_pass interleaves a few per thread on scenes larger than the caches). The arithmetic and the
// sampler's draws are those of the path traced from start to end, so the radiance is the same, bit for bit,
// however paths are interleaved: trace_path is start() and step() until it returns false.
class PathWalker {
public:
    // Starts the path of camera ray `ray`; `sampler` has been started for its pixel and sample, and belongs to this
    // path until it ends. The scene, settings and sampler must outlive the path.
    void start(const TraceableScene& ts, const RenderSettings& settings, Ray ray, Sampler& sampler);
    // Reports the path started last to `observer` (nullptr: none; start() clears it), which must outlive the path.
    void observe(PathObserver* observer) { m_observer = observer; }
    // Advances the path; false once it has ended (radiance() and counters() are then its results).
    bool step() { return (this->*m_step)(); }
    vec3 radiance() const { return m_L; }
    // Light groups (core/render/light_groups.h): with `groups` (nullptr: none; start() clears it, so call this after
    // it), the path also keeps its radiance per group, each contribution credited to the group of the light that
    // produced it; group_radiance() then has groups->count() entries. The radiance itself is unchanged, bit for bit.
    void group_by(const LightGroups* groups) {
        m_groups = groups;
        if (groups) std::fill_n(m_group_L.begin(), groups->count(), vec3(0.f));
    }
    const vec3* group_radiance() const { return m_group_L.data(); }
    const PathCounters& counters() const { return m_counters; }

private:
    enum class Stage : uint8_t { Trace, Surface, Scatter };
    enum class Next : uint8_t { Go, Wait, End };  // a stage's outcome: on to the next, wait for a prefetch, path ended
    struct Vertex;                                // the vertex being scattered (integrator.cpp)
    struct Draws;                                 // its sampler draws
    template <bool kPacked>
    bool step_with();
    // The stages and the parts of Scatter, each a function (integrator.cpp; inlined into step_with).
    template <bool kPacked>
    Next trace();
    void escape();
    template <bool kPacked>
    Next surface();
    void emission_found();
    Next scatter();
    Draws draw(const Bsdf& bsdf);
    void next_event(Vertex& v, const Draws& d);
    void punctual_lights(Vertex& v);
    Next continue_path(Vertex& v, const Draws& d);
    // The path's current medium (m_medium) along the segment to the hit (or to infinity): its free-flight distance,
    // and a scattering event there (next-event estimation through the medium, the phase function's sample) when one
    // is drawn.
    bool medium_segment(bool hit, float t_hit, Next& next);
    // Single scattering toward the point and spot lights along the segment, by equiangular sampling (u), MIS-weighted
    // against distance sampling's scattering events.
    void equiangular(const HomogeneousMedium& medium, float tmax, float u);
    // The scattering event at distance t of the segment (of length tmax; pdf_t: distance sampling's density there).
    Next medium_scatter(float t, float tmax, float pdf_t);
    vec3 medium_transmittance(float dist) const;
    // A transmission through a surface of material mat, into its solid (entering) or out of it: the medium stack.
    void cross_boundary(const Material& mat, bool entering);
    bool roulette(uint32_t dim);
    // The one place radiance joins the path: c, produced by a light of `group` (kEnvironmentGroup: the environment
    // toward dir, split between sky and sun), added to the path and, with light groups, to its group.
    void add(vec3 c, uint8_t group, vec3 dir = vec3(0.f)) {
        m_L += c;
        if (m_groups) [[unlikely]]
            credit(c, group, dir);
    }
    void credit(vec3 c, uint8_t group, vec3 dir);
    bool finish() {
        m_counters.paths = 1;
        return false;
    }
    const TraceableScene* m_ts = nullptr;
    const RenderSettings* m_settings = nullptr;
    Sampler* m_sampler = nullptr;
    PathObserver* m_observer = nullptr;
    const LightGroups* m_groups = nullptr;
    std::array<vec3, kMaxLightGroups> m_group_L;
    bool (PathWalker::*m_step)() = nullptr;
    Stage m_stage = Stage::Trace;
    bool m_nee = false, m_mis = false, m_select_draw = false, m_early_sky = false;
    // The path.
    Ray m_ray;
    vec3 m_L{0.f}, m_beta{1.f};
    bool m_specular_bounce = true;
    float m_prev_pdf = 0.f;  // solid-angle pdf of the BSDF sample that produced m_ray
    vec3 m_prev_p{0.f};
    vec3 m_prev_n{0.f};  // the shading normal there (the light tree's pick depends on it)
    float m_eta_scale = 1.f;
    // Inside an absorbing solid (a metallic-roughness material with KHR_materials_volume attenuation): its
    // Beer-Lambert coefficient, applied to the segment to the next hit.
    bool m_absorbing = false;
    vec3 m_sigma{0.f};
    // Media (docs/media.md): any in the scene (m_media: the one flag a scene without media tests), the medium the
    // path is in (nullptr: none), and the closed transmissive solids it is inside, innermost last.
    bool m_media = false;
    bool m_equiangular = false;  // point or spot lights, sampled (light sampling on), with media
    const HomogeneousMedium* m_medium = nullptr;
    const Material* m_solids[kMaxMediumNesting] = {};
    int m_nesting = 0;
    int m_depth = 0;
    PathCounters m_counters;
    // The vertex in flight, from one stage to the next.
    Hit m_hit;
    const TriangleRecord* m_record = nullptr;
    bool m_early = false, m_early_found = false;  // the environment's light sample drawn at the hit (m_early_sky)
    uint32_t m_early_dim = 0;
    vec2 m_early_u{0.f};
    LightSample m_early_ls;
    SurfacePoint m_sf;
    const Material* m_mat = nullptr;
    bool m_front = false;
    HitTextures m_tex;        // the hit's per-hit BSDF inputs (core/render/shading.h)
    TexelFootprint m_texels;  // m_tex.base_color's prefetched texels
};

// Radiance arriving along `ray` in `scene` (shared read-only by all threads). Uses kBounceDims sampler dimensions
// per bounce.
vec3 trace_path(const TraceableScene& ts, const RenderSettings& settings, Ray ray, Sampler& sampler,
                PathCounters& counters);

}  // namespace pv
