// ui/restarts.h: what the viewer asks of the ProgressiveRenderer. A frame's changes name the reason for a restart;
// the request carries the camera, the estimator and the image region divided by the refinement level, and the
// edited materials and environment only when they changed; a posted request goes to the refinement schedule and
// the log. Pause and targets are run controls: they never restart. Window-free.
#pragma once

#include <string>

#include "core/frame/progressive.h"
#include "panel.h"
#include "refinement.h"
#include "view_log.h"

namespace pv::ui {

// "camera,settings,material,environment,region,resize,restart" for the changes present, in that order; "" for none.
std::string restart_reason(const PanelActions& act, bool camera_moved, bool resized);

// The request for an image region of full_w x full_h pixels at resolution divisor `level` (at least 1x1), with
// state.region scaled to that level (none while adaptive sampling is on: the renderer refuses the two together).
RenderRequest make_request(const ViewState& state, const CameraDesc& camera, int full_w, int full_h, int level,
                           bool with_materials, bool with_environment);

// Posts `request` for `restart`: on success the schedule learns its generation and the log gets a "restart" line;
// a request the renderer refuses (pv::Error) is logged and dropped.
void post_restart(ProgressiveRenderer& renderer, RefinementSchedule& schedule,
                  const RefinementSchedule::Restart& restart, const RenderRequest& request, ViewLog& log, double now);

// A frame's changes, as restart_on_change() takes them.
struct FrameChanges {
    const PanelActions& act;
    bool camera_moved = false;
    bool resized = false;
    double since = 0.0;  // glfwGetTime() of the first input event not yet handled, else `now`
    double now = 0.0;
};

// A frame's changes reach the renderer: run controls applied (they never restart), then the restart the schedule
// asks for (a change, or refinement at rest), posted for the camera and an image region of full_w x full_h.
void restart_on_change(ProgressiveRenderer& renderer, RefinementSchedule& schedule, const ViewState& state,
                       const CameraDesc& camera, int full_w, int full_h, const FrameChanges& changes,
                       const Snapshot& shown, bool minimised, ViewLog& log);

// Pause (the user's, or while minimised) and the spp / seconds targets.
void apply_controls(ProgressiveRenderer& renderer, const ViewState& state, bool minimised);

}  // namespace pv::ui
