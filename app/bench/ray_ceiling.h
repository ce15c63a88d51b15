// app/bench/ray_ceiling.h: the ray-rate section of `pathview bench` (--rays, --rays-only): the path tracer's ray
// rate against Embree's raw rate on the same scene and ray mix (app/bench/raybench.h), and the minimal kernel's.
#pragma once

#include <memory>

#include "app/bench/options.h"
#include "app/progress.h"
#include "core/scene/scene.h"

namespace pv::app {

// Prints the ray-rate table (--rays-rounds rounds at --threads, and at 1 thread with --scaling) and the medians.
void rays_section(const BenchOptions& o, std::shared_ptr<const Scene> scene, const CameraDesc& camera,
                  ProgressBar& progress);

}  // namespace pv::app
