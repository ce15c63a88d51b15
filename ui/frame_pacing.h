// ui/frame_pacing.h: when the viewer's loop draws. It sleeps until input, a published pass or an expiring deferral
// arrives, unless the camera is in motion (held fly keys, settle frames after input); then never sooner than one
// display refresh after the previous frame, and a press, scroll, drop or drag after half a refresh. Needs GLFW.
#pragma once

#include <functional>

#include "input.h"
#include "navigation.h"

namespace pv::ui {

// The facts navigation.h needs about this frame: cursor, image region (framebuffer pixels `image_fb`, `fb_scale`
// framebuffer pixels per window pixel), ImGui's wishes, the time step and the picking function.
NavigationFrame read_navigation_frame(GLFWwindow* window, vec2 image_fb, float fb_scale, double dt,
                                      std::function<std::optional<PickResult>(vec2)> pick);

class FramePacing {
public:
    // Waits as above. `published` tells whether a newer pass than the one shown is ready; `deferral_wait` is how long
    // a deferred camera move may wait (RefinementSchedule::wait_timeout), `refresh_hz` the display's rate.
    void wait(const InputQueue& input, bool imgui_wants_keyboard, double deferral_wait, double refresh_hz,
              const std::function<bool()>& published);
    // Whether frames are drawn without waiting for events (held fly keys send none; settle frames follow input).
    bool continuous(const InputQueue& input, bool imgui_wants_keyboard) const;
    // While the window is minimised (or has no pixels): sleeps until an event and returns true. `on_change(minimised)`
    // runs when that state changes (the viewer pauses or resumes rendering); input after it draws a frame.
    bool sleep_while_minimised(GLFWwindow* window, InputQueue& input, const std::function<void(bool)>& on_change);
    bool is_minimised() const { return m_minimised; }  // as the last call found
    // A frame starts at `now`: the time step for camera motion (0 on the first frame, at most 0.1 s).
    double begin_frame(double now, bool input);

private:
    double m_last_frame = -1.0;
    int m_settle_frames = 0;
    bool m_minimised = false;
};

}  // namespace pv::ui
