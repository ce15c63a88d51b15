// ui/restarts.cpp: restart requests (see restarts.h).
#include "restarts.h"

#include <algorithm>
#include <cstdio>

#include "core/base/error.h"

namespace pv::ui {

std::string restart_reason(const PanelActions& act, bool camera_moved, bool resized) {
    std::string reason;
    auto add = [&](const char* r) { reason += (reason.empty() ? "" : ",") + std::string(r); };
    if (camera_moved || act.camera_changed || act.frame_all || act.reset_camera) add("camera");
    if (act.settings_changed) add("settings");
    if (act.materials_changed) add("material");
    if (act.environment_changed) add("environment");
    if (act.region_changed) add("region");
    if (resized) add("resize");
    if (act.restart) add("restart");
    return reason;
}

RenderRequest make_request(const ViewState& state, const CameraDesc& camera, int full_w, int full_h, int level,
                           bool with_materials, bool with_environment) {
    RenderRequest req;
    if (with_environment) {
        req.environment = state.environment;
        req.fog = state.fog;
    }
    req.camera = camera;
    req.settings = state.settings;
    req.adaptive = state.adaptive;
    req.width = std::max(1, full_w / level);
    req.height = std::max(1, full_h / level);
    if (with_materials) req.materials = state.materials;
    // The region in this level's pixels: every full-resolution pixel it covers stays covered.
    if (state.region && !state.adaptive.enabled() && !state.adaptive.allocate) {
        const PixelRect& r = *state.region;
        req.region = PixelRect{std::min(r.x0 / level, req.width - 1), std::min(r.y0 / level, req.height - 1),
                               std::clamp((r.x1 + level - 1) / level, 1, req.width),
                               std::clamp((r.y1 + level - 1) / level, 1, req.height)};
        if (req.region->empty()) req.region.reset();
    }
    return req;
}

void post_restart(ProgressiveRenderer& renderer, RefinementSchedule& schedule,
                  const RefinementSchedule::Restart& restart, const RenderRequest& request, ViewLog& log, double now) {
    uint64_t generation = 0;
    try {
        generation = renderer.restart(request);
    } catch (const Error& e) {
        log.line("restart-error %s", e.what());
        return;
    }
    schedule.posted(generation, restart, now);
    log.line("restart gen=%llu reason=%s size=%dx%d level=%d %s", (unsigned long long)generation,
             restart.reason.c_str(), request.width, request.height, schedule.level(),
             request.settings.describe().c_str());
}

void apply_controls(ProgressiveRenderer& renderer, const ViewState& state, bool minimised) {
    renderer.set_paused(state.paused || minimised);
    renderer.set_target(uint32_t(state.target_spp), double(state.target_seconds));
    if (!state.light_mix.empty()) renderer.set_light_gains(light_mix_gains(state.light_mix));
}

void restart_on_change(ProgressiveRenderer& renderer, RefinementSchedule& schedule, const ViewState& state,
                       const CameraDesc& camera, int full_w, int full_h, const FrameChanges& c, const Snapshot& shown,
                       bool minimised, ViewLog& log) {
    if (c.act.control_changed) {
        apply_controls(renderer, state, minimised);
        log.line("control paused=%d target_spp=%d target_seconds=%g", int(state.paused), state.target_spp,
                 double(state.target_seconds));
    }
    if (c.act.light_mix_changed) {
        // The live mix: the film re-mixed on display, never a restart (docs/light-groups.md).
        const LightGains k = light_mix_gains(state.light_mix);
        renderer.set_light_gains(k);
        std::string gains;
        for (size_t i = 0; i < k.size(); ++i) {
            char buf[160];
            std::snprintf(buf, sizeof buf, " %s=%g,%g,%g", state.light_mix[i].name.c_str(), double(k[i].x),
                          double(k[i].y), double(k[i].z));
            gains += buf;
        }
        log.line("light-mix%s", gains.c_str());
    }
    const std::string reason = restart_reason(c.act, c.camera_moved, c.resized);
    if (const auto restart = schedule.update(reason, c.now, c.since, shown.generation, shown.spp)) {
        const RenderRequest req = make_request(state, camera, full_w, full_h, schedule.level(), c.act.materials_changed,
                                               c.act.environment_changed);
        post_restart(renderer, schedule, *restart, req, log, c.now);
    }
}

}  // namespace pv::ui
