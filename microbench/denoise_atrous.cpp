// microbench/denoise_atrous.cpp: the interactive denoiser's time per 512x512 frame of the built-in Cornell box
// (4 spp, first-hit features), on the calling thread only: a fresh call (features laid out and memory allocated
// every time) and the viewer's per-frame cost (one denoiser kept, features laid out once). Run:
// build/microbench/pathview_microbench_denoise
#include "core/denoise/denoise_atrous.h"

#include <benchmark/benchmark.h>

#include "core/denoise/aov.h"
#include "core/frame/renderer.h"
#include "core/load/scene_file.h"

namespace {

struct Frame {
    pv::Image mean, variance;
    pv::FeatureImage features;
};

const Frame& cornell_frame() {
    static const Frame frame = [] {
        auto scene = std::make_shared<pv::Scene>(pv::load_scene(pv::builtin_scene_path()));
        pv::Renderer r(scene, 0);
        r.restart(scene->camera, pv::RenderSettings{}, 512, 512);
        for (int i = 0; i < 4; ++i) r.render_pass();
        return Frame{r.film().mean(), r.film().variance_of_mean(),
                     pv::render_features(r.traceable(), r.camera(), 512, 512, 4)};
    }();
    return frame;
}

void BM_AtrousCornell512(benchmark::State& state) {
    const Frame& f = cornell_frame();
    for (auto _ : state) benchmark::DoNotOptimize(pv::denoise_atrous(f.mean, f.variance, f.features));
    state.SetItemsProcessed(state.iterations() * 512 * 512);
}
BENCHMARK(BM_AtrousCornell512)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

// What the viewer pays per new pass: one denoiser kept across frames, its features laid out once per camera.
void BM_AtrousCornell512PerFrame(benchmark::State& state) {
    const Frame& f = cornell_frame();
    pv::AtrousDenoiser d;
    pv::Image out;
    d.set_features(f.features);
    for (auto _ : state) {
        d.denoise(f.mean, f.variance, out);
        benchmark::DoNotOptimize(out.rgb.data());
    }
    state.SetItemsProcessed(state.iterations() * 512 * 512);
}
BENCHMARK(BM_AtrousCornell512PerFrame)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
