// app/render_plan.cpp: `pathview render`'s request checked and planned (see render_plan.h).
#include "app/render_plan.h"

#include "core/base/error.h"

namespace pv {
namespace {

// The flag that makes a render partial: --shard, --samples or --resume (`order` picks which is named first).
std::string partial_flag(const RenderRequest& r, bool resume_before_samples = false) {
    if (!r.shard.empty()) return "--shard";
    if (resume_before_samples) return !r.resume.empty() ? "--resume" : "--samples";
    return !r.samples.empty() ? "--samples" : "--resume";
}

// Flags that cannot be combined, each refused with one line.
void check_combinations(const RenderRequest& r) {
    const bool partial = !r.shard.empty() || !r.samples.empty() || !r.resume.empty();
    // The layers of --aovs and --denoise are not part of the partial format: refused rather than dropped.
    if ((r.aovs || r.denoise) && partial)
        throw Error(std::string(r.aovs ? "--aovs" : "--denoise") + " with " + partial_flag(r) +
                    ": a partial render holds only the film's sums, not feature layers or a denoised image; render "
                    "the parts without it (merge them, then denoise a full render)");
    // A region is not part of the partial format (merging parts of different regions would mix images): refused.
    if (!r.region.empty() && partial)
        throw Error("--region with " + partial_flag(r) +
                    ": partial renders cover the whole image; render the region without it");
    if (!r.region.empty() && r.denoise)
        throw Error(
            "--region with --denoise: the denoiser would blend the black outside the region into its edges; "
            "denoise a full render");
    if (!r.region.empty() && (r.adaptive.allocate || r.adaptive.enabled()))
        throw Error(std::string("--region with ") + (r.adaptive.allocate ? "--adaptive on" : "--noise-threshold") +
                    ": adaptive sampling cannot be combined with a render region");
}

// The sample range START:COUNT of --samples.
SampleRange parse_samples(const std::string& text) {
    const std::vector<SampleRange> r = parse_ranges(text, "--samples " + quote_prefix(text));
    if (r.size() != 1 || r[0].count > (1u << 30))
        throw Error("--samples " + quote_prefix(text) + ": expected one START:COUNT with COUNT <= 2^30");
    return r[0];
}

// --resume: the part read, and the scene and the next sample index taken from it.
void plan_resume(const RenderRequest& r, RenderPlan& plan,
                 const std::function<void(const PartialRender&)>& on_resumed) {
    for (const std::string& flag : r.image_flags_given)
        throw Error("--resume " + r.resume + ": " + flag + " comes from the part; leave it out");
    plan.resumed = read_partial(r.resume);
    if (on_resumed) on_resumed(*plan.resumed);
    if (plan.scene.empty()) {
        const auto it = plan.resumed->info.find("pathview:scene");
        plan.scene = it == plan.resumed->info.end() ? "" : it->second;
        if (plan.scene.size() > 4096)  // PATH_MAX: not a path this system can open
            throw Error("--resume " + r.resume + ": pathview:scene " + quote_prefix(plan.scene) +
                        " is longer than a path can be; give the scene file as an argument");
    }
    plan.samples = SampleRange{plan.resumed->ranges.back().end(), 0};
    if (plan.samples->start + uint64_t(plan.spp.value_or(1)) > kSampleIndexLimit)
        throw Error("--resume " + r.resume + ": the part ends at sample " + std::to_string(plan.samples->start) +
                    "; no room for " + std::to_string(plan.spp.value_or(1)) +
                    " more samples (sample indices end at 2^32)");
}

}  // namespace

RenderPlan plan_render(const RenderRequest& r, const std::function<void(const PartialRender&)>& on_resumed) {
    RenderPlan plan;
    plan.spp = r.spp;
    plan.seconds = r.seconds;
    plan.adaptive = r.adaptive;
    plan.scene = r.scene;
    if (!plan.spp && !plan.seconds) plan.spp = 64;
    check_combinations(r);
    // A partial render: --samples START:COUNT renders those indices; --resume continues a part after its last index.
    if (!r.shard.empty()) {
        uint64_t index = 0, shards = 0;
        parse_shard(r.shard, index, shards);
        plan.samples = shard_range(index, shards, uint64_t(*plan.spp));
        plan.spp = int(plan.samples->count);
    }
    if (!r.samples.empty()) {
        plan.samples = parse_samples(r.samples);
        if (!plan.seconds) plan.spp = int(plan.samples->count);
    }
    if (!r.resume.empty()) plan_resume(r, plan, on_resumed);
    // A partial render samples every pixel at each of its indices, so that its parts merge into what one `render
    // --adaptive off` gives, bit for bit. Adaptive sampling cannot be split so: each pixel's allocation comes from a
    // pilot over the whole render (core/frame/adaptive.h), so --adaptive on is refused with a partial render.
    if (plan.samples && plan.adaptive.allocate) {
        if (r.adaptive_given)
            throw Error(partial_flag(r, true) +
                        ": a partial render samples every pixel at every index (so that parts merge bit for bit); "
                        "--adaptive on cannot be split so: leave it out or give --adaptive off");
        plan.adaptive.allocate = false;
    }
    return plan;
}

bool RenderPlan::done(uint32_t spp_done, double elapsed, bool converged) const {
    if (spp && spp_done >= static_cast<uint32_t>(*spp)) return true;
    // A partial render with --time: at most COUNT samples (--samples), never past the index space (--resume).
    if (samples && spp_done >= (samples->count ? samples->count : kSampleIndexLimit - samples->start)) return true;
    if (seconds && elapsed >= *seconds && spp_done > 0) return true;
    return converged;
}

}  // namespace pv
