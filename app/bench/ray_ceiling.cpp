// app/bench/ray_ceiling.cpp: the bench's ray-rate section (see ray_ceiling.h).
#include "app/bench/ray_ceiling.h"

#include <algorithm>
#include <cstdio>
#include <memory>

#include "app/bench/raybench.h"
#include "app/bench/series.h"
#include "core/frame/renderer.h"

namespace pv::app {

void rays_section(const BenchOptions& o, std::shared_ptr<const Scene> scene, const CameraDesc& camera,
                  ProgressBar& progress) {
    std::vector<int> thread_counts;
    Renderer probe(scene, o.common.threads);
    const int n = probe.threads();
    if (o.scaling && n > 1) thread_counts.push_back(1);
    thread_counts.push_back(n);
    RenderSettings settings = o.common.settings;
    std::printf("\n### Ray-rate ceiling: %s, %dx%d, %s, %s clock\n\n", scene->source.c_str(), o.common.width,
                o.common.height, settings.describe().c_str(), o.clock.c_str());
    std::printf("BVH: %zu triangles, build %.3f s, %.2f MiB (Embree memory monitor)\n\n", scene->triangle_count(),
                probe.traceable().accel().stats().build_seconds,
                double(probe.traceable().accel().stats().bytes) / (1024.0 * 1024.0));
    std::printf(
        "| threads | round | path tracer Mrays/s | Embree camera | Embree bounce | Embree shadow | Embree on the "
        "path tracer's mix | fraction of ceiling | minimal kernel Mrays/s | its fraction |\n"
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    std::vector<std::pair<int, double>> medians, minimal_medians;
    for (int threads : thread_counts) {
        // The probe serves the full thread count; only --scaling's 1-thread run builds a second BVH.
        std::unique_ptr<Renderer> single;
        if (threads != n) single = std::make_unique<Renderer>(scene, threads);
        Renderer& r = single ? *single : probe;
        std::vector<double> fractions, minimal_fractions;
        double pt_sum = 0, ceil_sum = 0, mk_sum = 0, mk_ceil_sum = 0;
        for (int round = 0; round < o.rays_rounds; ++round) {
            progress.draw(double(round) / o.rays_rounds, "ray rates, " + std::to_string(threads) + " threads");
            r.restart(camera, settings, o.common.width, o.common.height);
            r.render_pass();  // warm-up pass, not counted
            r.restart(camera, settings, o.common.width, o.common.height);
            double seconds = 0.0;
            while (seconds < o.rays_seconds) seconds += timed_pass(r, o.clock == "cpu");
            const RenderStats& st = r.stats();
            const double pt = double(st.rays + st.shadow_rays) / seconds;
            RayMix mix;
            mix.camera = double(st.paths);
            mix.bounce = double(st.rays - st.paths);
            mix.shadow = double(st.shadow_rays);
            RayBenchOptions ro;
            ro.width = o.common.width;
            ro.height = o.common.height;
            ro.threads = threads;
            ro.seconds_per_kind = o.rays_seconds / 3.0;
            ro.seed = 17u + uint32_t(round);
            ro.cpu_clock = o.clock == "cpu";
            const RayRates rates = measure_ray_rates(r.traceable(), r.camera(), ro);
            const double ceiling = rates.mix_rate(mix);
            const MinimalKernelRate mk = measure_minimal_kernel(r.traceable(), r.camera(), ro);
            const double mk_ceiling = rates.mix_rate(mk.mix);
            fractions.push_back(pt / ceiling);
            minimal_fractions.push_back(mk.rays_per_second / mk_ceiling);
            pt_sum += pt;
            ceil_sum += ceiling;
            mk_sum += mk.rays_per_second;
            mk_ceil_sum += mk_ceiling;
            std::printf("| %d | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.3f | %.2f | %.3f |\n", threads, round + 1,
                        pt * 1e-6, rates.camera * 1e-6, rates.bounce * 1e-6, rates.shadow * 1e-6, ceiling * 1e-6,
                        pt / ceiling, mk.rays_per_second * 1e-6, mk.rays_per_second / mk_ceiling);
            std::fflush(stdout);
        }
        std::sort(fractions.begin(), fractions.end());
        std::sort(minimal_fractions.begin(), minimal_fractions.end());
        medians.emplace_back(threads, fractions[fractions.size() / 2]);
        minimal_medians.emplace_back(threads, minimal_fractions[minimal_fractions.size() / 2]);
        std::printf("| %d | mean | %.2f | | | | %.2f | %.3f | %.2f | %.3f |\n", threads, pt_sum / o.rays_rounds * 1e-6,
                    ceil_sum / o.rays_rounds * 1e-6, pt_sum / ceil_sum, mk_sum / o.rays_rounds * 1e-6,
                    mk_sum / mk_ceil_sum);
    }
    std::printf("\n");
    for (size_t i = 0; i < medians.size(); ++i)
        std::printf(
            "Path tracer at %d thread%s: median %.3f of Embree's raw rate on the same ray mix (minimal kernel: "
            "%.3f of the rate on its own mix).\n",
            medians[i].first, medians[i].first == 1 ? "" : "s", medians[i].second, minimal_medians[i].second);
    std::printf(
        "The minimal kernel (white Lambertian, one shadow ray per vertex, PCG numbers, no MIS, roulette, "
        "materials, Sobol or film) bounds what per-ray shading code reaches on this scene.\n");
}

}  // namespace pv::app
