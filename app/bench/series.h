// app/bench/series.h: the spp/time series of `pathview bench`: per configuration and seed, a doubling series of spp
// within the time budget, measured against the reference at each power of two and summarised over the seeds.
#pragma once

#include "app/bench.h"
#include "app/bench/options.h"
#include "app/progress.h"
#include "core/frame/renderer.h"

namespace pv::app {

// One render pass; returns its duration by the chosen clock (wall, or process CPU time / threads).
double timed_pass(Renderer& r, bool cpu_clock);
// The seeds' samples at one spp: spreads over the seeds, ray rates and path lengths.
BenchPoint summarise(const std::vector<BenchSample>& samples);
// Renders seed after seed of one configuration. The first seed fixes the spp series: powers of two while the next
// doubling fits in the budget (from the time the current spp took); the other seeds render the same series. The
// progress bar goes from progress_base to progress_base + progress_step.
BenchSeries run_series(const BenchOptions& o, const BenchConfig& config, Renderer& renderer, const CameraDesc& camera,
                       const Image& reference, ProgressBar& progress, double progress_base, double progress_step);

}  // namespace pv::app
