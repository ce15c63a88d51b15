// app/render_plan.h: what `pathview render` asked for, checked and turned into a plan before anything is
// loaded: the sample count or time, the partial render's sample indices (--samples, --shard, --resume), the part to
// continue, and the adaptive sampling that applies. Combinations that cannot work are refused here with one line.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/frame/adaptive.h"
#include "core/partial/partial.h"

namespace pv {

// The command line's request (strings as given; empty: not given).
struct RenderRequest {
    std::optional<int> spp;         // --spp
    std::optional<double> seconds;  // --time
    std::string samples;            // --samples START:COUNT
    std::string resume;             // --resume PART.exr
    std::string shard;              // --shard I/N
    std::string region;             // --region x0,y0,x1,y1
    bool aovs = false, denoise = false;
    AdaptiveSettings adaptive;                   // --adaptive, --noise-threshold, --min-spp
    bool adaptive_given = false;                 // --adaptive was on the command line
    std::string scene;                           // the scene argument (empty: none)
    std::vector<std::string> image_flags_given;  // flags given that define the image (refused with --resume)
};

struct RenderPlan {
    std::optional<int> spp;                // samples per pixel to render (64 when neither --spp nor --time)
    std::optional<double> seconds;         // --time
    std::optional<SampleRange> samples;    // a partial render: its first index and at most `count` samples (0: any)
    std::optional<PartialRender> resumed;  // --resume's part
    AdaptiveSettings adaptive;             // the request's, without allocation for a partial render
    std::string scene;                     // the scene argument, or the resumed part's scene

    // Whether a render that has taken `spp_done` passes in `elapsed` seconds (`converged`: the noise threshold is met
    // everywhere) is finished.
    bool done(uint32_t spp_done, double elapsed, bool converged) const;
};

// The plan of `request`, or pv::Error naming the flags that do not go together. `on_resumed`, when given, sees the
// resumed part as soon as it is read (the command line applies its scene flags then).
RenderPlan plan_render(const RenderRequest& request,
                       const std::function<void(const PartialRender&)>& on_resumed = nullptr);

}  // namespace pv
