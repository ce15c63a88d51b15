// ui/frame_pacing.cpp: see frame_pacing.h.
#include "frame_pacing.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <utility>

namespace pv::ui {

NavigationFrame read_navigation_frame(GLFWwindow* window, vec2 image_fb, float fb_scale, double dt,
                                      std::function<std::optional<PickResult>(vec2)> pick) {
    NavigationFrame f;
    double cx, cy;
    glfwGetCursorPos(window, &cx, &cy);
    f.cursor = vec2(float(cx), float(cy));
    f.image_size = image_fb / fb_scale;
    f.render_size = image_fb;
    glfwGetWindowSize(window, nullptr, &f.window_height);
    f.imgui_wants_mouse = ImGui::GetIO().WantCaptureMouse;
    f.imgui_wants_keyboard = ImGui::GetIO().WantCaptureKeyboard;
    f.dt = dt;
    f.pick = std::move(pick);
    return f;
}

bool FramePacing::continuous(const InputQueue& input, bool imgui_wants_keyboard) const {
    bool fly_keys = false;
    for (bool k : input.fly_down) fly_keys = fly_keys || (k && !imgui_wants_keyboard);
    return fly_keys || m_settle_frames > 0;
}

void FramePacing::wait(const InputQueue& input, bool imgui_wants_keyboard, double deferral_wait, double refresh_hz,
                       const std::function<bool()>& published) {
    // A deferred camera move needs a frame when its wait expires, even if nothing else happens.
    if (!continuous(input, imgui_wants_keyboard) && !input.any) glfwWaitEventsTimeout(deferral_wait);
    // The first pass of a new accumulation is shown at once, though: it answers an input event. A press, scroll,
    // drop or drag is handled after half a refresh (at most two frames a refresh): waiting out the whole refresh put
    // up to 17 ms between a drag and the restart it posts.
    const double next = m_last_frame + 1.0 / refresh_hz;
    const double next_urgent = m_last_frame + 0.5 / refresh_hz;
    for (double now = glfwGetTime(); now < next; now = glfwGetTime()) {
        if (published()) break;
        if (input.urgent && now >= next_urgent) break;
        glfwWaitEventsTimeout((input.urgent ? next_urgent : next) - now);
    }
    glfwPollEvents();
}

bool FramePacing::sleep_while_minimised(GLFWwindow* window, InputQueue& input,
                                        const std::function<void(bool)>& on_change) {
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    const bool now = glfwGetWindowAttrib(window, GLFW_ICONIFIED) || fb_w == 0 || fb_h == 0;
    if (now != m_minimised) {
        m_minimised = now;
        on_change(now);
        input.any = input.any || !now;
    }
    if (!now) return false;
    glfwWaitEvents();
    input.first_event = -1.0;
    return true;
}

double FramePacing::begin_frame(double now, bool input) {
    const double dt = m_last_frame < 0.0 ? 0.0 : std::min(now - m_last_frame, 0.1);
    m_last_frame = now;
    m_settle_frames = input ? 2 : std::max(m_settle_frames - 1, 0);
    return dt;
}

}  // namespace pv::ui
