// app/bench/series.cpp: the bench's convergence series (see series.h).
#include "app/bench/series.h"

#include <algorithm>
#include <chrono>

#include "app/bench/raybench.h"
#include "core/denoise/aov.h"
#include "core/denoise/denoise_atrous.h"
#include "core/frame/render_output.h"

namespace pv::app {

double timed_pass(Renderer& r, bool cpu_clock) {
    const double c0 = process_cpu_seconds();
    const double w0 = r.stats().seconds;
    r.render_pass();
    return cpu_clock ? (process_cpu_seconds() - c0) / r.threads() : r.stats().seconds - w0;
}

BenchPoint summarise(const std::vector<BenchSample>& samples) {
    BenchPoint p;
    p.spp = samples.front().spp;
    p.seeds = static_cast<int>(samples.size());
    std::vector<double> t, rel, rmse, mape, trimmed;
    double rays = 0, paths = 0, vertices = 0, secs = 0;
    for (const BenchSample& s : samples) {
        t.push_back(s.seconds);
        rel.push_back(s.error.rel_mse);
        rmse.push_back(s.error.rmse);
        mape.push_back(s.error.mape);
        trimmed.push_back(s.rel_mse_trimmed);
        rays += s.rays + s.shadow_rays;
        paths += s.paths;
        vertices += s.vertices;
        secs += s.seconds;
    }
    p.seconds = spread_of(t);
    p.rel_mse = spread_of(rel);
    p.rmse = spread_of(rmse);
    p.mape = spread_of(mape);
    p.rel_mse_trimmed = spread_of(trimmed);
    p.mrays_per_s = secs > 0 ? rays / secs * 1e-6 : 0.0;
    p.mean_path_length = paths > 0 ? vertices / paths : 0.0;
    p.rays_per_sample = paths > 0 ? rays / paths : 0.0;
    p.denoised = samples.front().nfor_seconds > 0.0;
    if (p.denoised) {
        std::vector<double> ra, ta, rn, tn;
        for (const BenchSample& s : samples) {
            ra.push_back(s.rel_mse_atrous);
            ta.push_back(s.atrous_seconds);
            rn.push_back(s.rel_mse_nfor);
            tn.push_back(s.nfor_seconds);
        }
        p.rel_mse_atrous = spread_of(ra);
        p.atrous_seconds = spread_of(ta);
        p.rel_mse_nfor = spread_of(rn);
        p.nfor_seconds = spread_of(tn);
    }
    return p;
}

BenchSeries run_series(const BenchOptions& o, const BenchConfig& config, Renderer& renderer, const CameraDesc& camera,
                       const Image& reference, ProgressBar& progress, double progress_base, double progress_step) {
    std::vector<std::vector<BenchSample>> by_point;
    uint32_t last_spp = 0;
    FeatureImage features;  // the camera's first-hit features, for --denoise (same for every seed)
    AtrousDenoiser atrous;  // lays the features out once, as the viewer's filter does; each point times denoise()
    Image atrous_image;
    if (o.denoise) {
        renderer.restart(camera, config.settings, o.common.width, o.common.height);
        features = render_features(renderer.traceable(), renderer.camera(), o.common.width, o.common.height);
        atrous.set_features(features);
    }
    for (int seed = 0; seed < o.seeds; ++seed) {
        RenderSettings s = config.settings;
        s.seed = o.common.settings.seed + 1u + uint32_t(seed);
        renderer.restart(camera, s, o.common.width, o.common.height);
        size_t point = 0;
        double seconds = 0.0;
        for (uint32_t target = 1;; target *= 2) {
            while (renderer.stats().spp < target && !renderer.converged())
                seconds += timed_pass(renderer, o.clock == "cpu");
            const RenderStats& st = renderer.stats();
            BenchSample smp;
            smp.spp = st.spp;
            smp.seconds = seconds;
            const Image mean = renderer.film().mean();
            smp.error = compare_images(mean, reference);
            smp.rel_mse_trimmed = compare_images(mean, reference, kMetricEps, 0.001).rel_mse;
            if (o.denoise && (o.denoise_spp.empty() ||
                              std::find(o.denoise_spp.begin(), o.denoise_spp.end(), st.spp) != o.denoise_spp.end())) {
                const auto t0 = std::chrono::steady_clock::now();
                atrous.denoise(mean, renderer.film().variance_of_mean(), atrous_image);
                smp.atrous_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                smp.rel_mse_atrous = compare_images(atrous_image, reference).rel_mse;
                NforStats nfor;
                smp.rel_mse_nfor =
                    compare_images(denoise_film(renderer.film(), features, Denoiser::Nfor, &nfor), reference).rel_mse;
                smp.nfor_seconds = nfor.seconds;
            }
            smp.rays = double(st.rays);
            smp.shadow_rays = double(st.shadow_rays);
            smp.paths = double(st.paths);
            smp.vertices = double(st.vertices);
            if (by_point.size() <= point) by_point.emplace_back();
            by_point[point++].push_back(smp);
            const double f = seed == 0 ? std::min(1.0, seconds / o.budget) : double(point) / by_point.size();
            progress.draw(progress_base + progress_step * (seed + f) / o.seeds,
                          config.name + " seed " + std::to_string(seed + 1) + "/" + std::to_string(o.seeds) + ", " +
                              std::to_string(st.spp) + " spp");
            const bool last = seed == 0 ? (seconds * 2.0 > o.budget || target * 2 > o.max_spp || renderer.converged())
                                        : target >= last_spp;
            if (last) {
                if (seed == 0) last_spp = target;
                break;
            }
        }
    }
    BenchSeries series;
    series.config = config;
    std::vector<double> spp, secs, rel;
    for (const auto& samples : by_point) {
        series.points.push_back(summarise(samples));
        const BenchPoint& p = series.points.back();
        // Fits skip spp < 4, where every estimator is still pre-asymptotic (low-discrepancy samplers reach their
        // asymptotic error slope only past a few samples per pixel).
        if (p.spp >= 4) {
            spp.push_back(p.spp);
            secs.push_back(p.seconds.mean);
            rel.push_back(p.rel_mse.mean);
        }
    }
    series.slope_spp = fit_loglog(spp, rel);
    series.slope_time = fit_loglog(secs, rel);
    return series;
}

}  // namespace pv::app
