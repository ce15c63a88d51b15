// app/bench/raybench.h: Embree's raw ray rate on a scene through pv::Accel, for the ray mix a path tracer traces:
// camera rays, incoherent bounce rays (cosine-distributed about the surface normal along random walks) and shadow
// rays to sampled light points (offset and bounded exactly as core/render/integrator.cpp does). The rays are generated
// first, then traced in a timed loop on `threads` workers: no shading, sampling or film work is timed.
#pragma once

#include <cstdint>

#include "core/render/traceable_scene.h"
#include "core/scene/camera.h"

namespace pv {

// How many rays of each kind a workload traced (e.g. from a render's counters).
struct RayMix {
    double camera = 0.0, bounce = 0.0, shadow = 0.0;
    double total() const { return camera + bounce + shadow; }
};

// Rays per second of each kind (closest hit for camera and bounce rays, occlusion for shadow rays).
struct RayRates {
    double camera = 0.0, bounce = 0.0, shadow = 0.0;
    // The rate Embree alone would sustain on `mix`: its rays divided by the sum of their times at these rates.
    double mix_rate(const RayMix& mix) const;
};

struct RayBenchOptions {
    int width = 256, height = 256;  // camera rays: one jittered ray per pixel
    int threads = 0;                // 0: all cores
    double seconds_per_kind = 0.5;  // timed tracing per ray kind (whole passes over the ray set)
    int walk_depth = 4;             // bounce rays per camera ray at most (random walk, stops on a miss)
    uint32_t seed = 1;
    // Time by the process's CPU time divided by `threads` instead of the wall clock: rates then do not fall when
    // other processes share the cores (their work is not ours), while our own spinning and stalls still count.
    bool cpu_clock = false;
};

// CPU time of this process (all threads), seconds.
double process_cpu_seconds();

// Measures the three rates on `scene`'s BVH. Shadow rays go to its light samples, emitters and environment alike
// (toward the environment unbounded, as the integrator traces them).
RayRates measure_ray_rates(const TraceableScene& scene, const Camera& camera, const RayBenchOptions& options);

// A minimal path kernel on the same scene, as a floor for the cost of shading: the random walk behind the
// recorded rays (white Lambertian everywhere, cosine bounces, one shadow ray per vertex, PCG numbers; no MIS,
// roulette, materials, low-discrepancy sampling or film), tracing its rays as it goes, on `threads` workers for at
// least seconds_per_kind. Its rate over Embree's rate on its own mix says how close any per-ray shading code can
// come to the ceiling on this scene.
struct MinimalKernelRate {
    double rays_per_second = 0.0;
    RayMix mix;             // the rays it traced
    double estimate = 0.0;  // mean direct-light estimate per camera ray (red), so the work is not optimised away
};
MinimalKernelRate measure_minimal_kernel(const TraceableScene& scene, const Camera& camera,
                                         const RayBenchOptions& options);

}  // namespace pv
