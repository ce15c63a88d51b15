// app/bench/options.h: the options of `pathview bench` (app/cmd_bench.cpp registers them on the CLI); the bench's
// parts (reference, series, ray ceiling) read them.
#pragma once

#include <string>
#include <vector>

#include "app/commands.h"

namespace pv::app {

struct BenchOptions {
    CommonOptions common;
    std::string reference;  // EXR to load
    uint32_t reference_spp = 4096;
    SamplerKind reference_sampler = SamplerKind::Independent;
    std::string reference_sampler_name = "independent";
    std::string save_reference;
    double budget = 0.5;  // seconds of rendering per (configuration, seed)
    std::string configs = "all";
    int seeds = 4;
    uint32_t max_spp = 1u << 16;
    std::string csv = "pathview-bench.csv", svg = "pathview-bench.svg";
    std::string title;
    bool rays = false, rays_only = false, scaling = false;
    bool light_tree = false;  // --light-tree: the light tree's build time and memory for 10^2..10^5 emitters, only
    double rays_seconds = 2.0;
    int rays_rounds = 3;
    std::string clock = "cpu";  // process CPU seconds / threads, or "wall"
    bool quiet = false;
    bool denoise = false;               // denoised columns: a-trous and NFOR at every point
    std::vector<uint32_t> denoise_spp;  // --denoise-spp: only at these points (implies denoise)
};

}  // namespace pv::app
