// app/bench/reference.h: the reference of `pathview bench`: loaded from an EXR (--reference) or rendered as two
// independent halves whose difference estimates its own error; optionally saved (--save-reference).
#pragma once

#include "app/bench.h"
#include "app/bench/options.h"
#include "app/progress.h"
#include "core/frame/renderer.h"

namespace pv::app {

// Loads or renders the reference at --width x --height; throws pv::Error naming the EXR when its size differs.
Reference make_reference(const BenchOptions& o, Renderer& renderer, const CameraDesc& camera, ProgressBar& progress);

}  // namespace pv::app
