// app/bench.h: the data of a `pathview bench` run (configurations, measured points) and its writers (table, CSV,
// SVG). Times are seconds of rendering (whole passes), errors are against the run's reference (core/image/metrics.h).
#pragma once

#include <string>
#include <vector>

#include "core/image/metrics.h"
#include "core/render/integrator.h"

namespace pv::app {

// One estimator configuration: "mis/rr/sobol" = NEE+MIS, Russian roulette on, Sobol sampler.
struct BenchConfig {
    std::string name;
    RenderSettings settings;
};

// Parses a comma-separated list of "estimator/rr/sampler[/light-sampler]" names (bsdf|nee|mis, rr|norr, ind|sobol,
// power|tree, each may be "*"; "all" = "*/*/*"; without the fourth field, base's light sampler). Throws pv::Error
// naming the bad entry.
std::vector<BenchConfig> parse_configs(const std::string& list, const RenderSettings& base);

// One snapshot of one seed's render.
struct BenchSample {
    uint32_t spp = 0;
    double seconds = 0.0;
    ErrorMetrics error;
    double rel_mse_trimmed = 0.0;  // relMSE without the largest 0.1% of per-value errors (fireflies)
    double rays = 0.0, shadow_rays = 0.0, paths = 0.0, vertices = 0.0;
    // With --denoise: the denoised images' relMSE against the reference and the filters' seconds (wall). The
    // columns above stay the noisy estimator's.
    double rel_mse_atrous = 0.0, atrous_seconds = 0.0, rel_mse_nfor = 0.0, nfor_seconds = 0.0;
};

// The seeds' samples at one spp, summarised.
struct BenchPoint {
    uint32_t spp = 0;
    int seeds = 0;
    Spread seconds, rel_mse, rmse, mape, rel_mse_trimmed;
    double mrays_per_s = 0.0;       // closest-hit + shadow rays per second, millions
    double mean_path_length = 0.0;  // surface interactions per path
    double rays_per_sample = 0.0;   // closest-hit + shadow rays per path
    bool denoised = false;          // the four spreads below are measured (bench --denoise)
    Spread rel_mse_atrous, atrous_seconds, rel_mse_nfor, nfor_seconds;
    double efficiency() const {
        return rel_mse.mean > 0 && seconds.mean > 0 ? 1.0 / (rel_mse.mean * seconds.mean) : 0.0;
    }
};

struct BenchSeries {
    BenchConfig config;
    std::vector<BenchPoint> points;  // increasing spp (powers of two)
    SlopeFit slope_spp, slope_time;  // log-log fits of mean relMSE
};

// The reference every error is measured against.
struct Reference {
    Image image;
    double expected_rel_mse = -1.0;  // its own estimated error (< 0: unknown)
    std::string origin;
};

// A pipe table (Markdown-compatible) of every point of every series.
void print_points_table(const std::vector<BenchSeries>& series);
// With --denoise: noisy and denoised relMSE and the filters' times at every point.
void print_denoise_table(const std::vector<BenchSeries>& series);
// The equal-time table (relMSE of each series interpolated log-log at the longest time all reached, against the
// mis/rr/ind baseline) and the reference check (its own error against the smallest measured one).
void print_summary(const std::vector<BenchSeries>& all, const Reference& ref);
void write_csv(const std::string& path, const std::string& scene, const std::vector<BenchSeries>& series);
// Two log-log panels (relMSE against seconds and against spp), one curve per configuration with the min-max
// spread over seeds as bars, and a slope -1 guide in each panel.
void write_svg(const std::string& path, const std::string& title, const std::vector<BenchSeries>& series);

}  // namespace pv::app
