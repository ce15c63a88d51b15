// ui/navigation.h: the viewer's gestures and shortcuts mapped to the camera and to panel actions. Window-free: it
// reads an InputQueue (filled by the GLFW callbacks) and what ImGui wants this frame, picks through a callback, and
// edits a CameraController, so the whole mapping is unit-tested without a display (tests/gui/test_ui_logic.cpp).
#pragma once

#include <functional>
#include <optional>

#include "camera_controller.h"
#include "input.h"
#include "panel.h"
#include "view_log.h"

// The gestures and shortcuts:
//   left drag: orbit; middle drag or shift+left drag: pan; ctrl+left drag: a render region (X clears it); wheel: dolly;
//   a press that moves less than kClickSlopPx is a click: select the material under it, or (after "pick focus") set the
//   focus plane there; a double click re-targets the orbit; W A S D Q E fly; F frame all; R reset; P pause; G focus
//   under the cursor; Ctrl+S snapshot (EXR), Ctrl+Shift+S the image on screen as PNG; T the next view transform;
//   Ctrl+Q quit. Comparison (compare.h): B holds the image as B, C cycles the
//   compare views, V flips between A and B, right drag moves the split view's divider. N: the raw accumulation or
//   the denoised image (state.display.denoise).

namespace pv::ui {

// This frame's facts the mapping needs, all in window pixels.
struct NavigationFrame {
    vec2 cursor{0.f};
    vec2 image_size{0.f};   // the image region, from the top-left corner of the window
    vec2 render_size{0.f};  // the image region in render (framebuffer) pixels; 0: image_size
    int window_height = 0;
    bool imgui_wants_mouse = false;
    bool imgui_wants_keyboard = false;
    double dt = 0.0;                                      // seconds since the previous frame (fly speed)
    std::function<std::optional<PickResult>(vec2)> pick;  // the surface under a window position
};

struct NavigationResult {
    bool camera_moved = false;
    bool quit = false;
};

class Navigation {
public:
    static constexpr double kDoubleClickSeconds = 0.35;
    static constexpr float kClickSlopPx = 3.f;

    explicit Navigation(ViewLog& log) : m_log(log) {}
    // Consumes the queue's button events, scroll and key presses (the held fly keys stay: they are state), moves
    // the camera, and sets act.save / frame_all / reset_camera / control_changed and state.paused,
    // state.selected_material, state.pick_focus, state.region (with act.region_changed) as the gestures ask.
    NavigationResult handle(InputQueue& input, const NavigationFrame& frame, CameraController& camera, ViewState& state,
                            PanelActions& act);
    bool dragging() const { return m_drag.active; }

private:
    // The stages of handle: button presses and releases (drags, clicks), then shortcuts.
    void handle_buttons(InputQueue& input, const NavigationFrame& frame, CameraController& camera, ViewState& state,
                        PanelActions& act, NavigationResult& result);
    void drag_to(vec2 p, const NavigationFrame& frame, CameraController& camera, PanelActions& act,
                 NavigationResult& result);
    void handle_keys(InputQueue& input, const NavigationFrame& frame, CameraController& camera, ViewState& state,
                     PanelActions& act, NavigationResult& result);
    // A ctrl+left drag from a to b (window pixels): the render region it covers, in render pixels.
    void set_region(vec2 a, vec2 b, const NavigationFrame& frame, ViewState& state, PanelActions& act);
    void click(vec2 pos, double time, const NavigationFrame& frame, CameraController& camera, ViewState& state,
               NavigationResult& result);

    struct Drag {
        bool active = false, moved = false, pan = false, region = false, divider = false;
        int button = 0;
        vec2 start{0.f}, last{0.f};
    };
    ViewLog& m_log;
    Drag m_drag;
    double m_last_click_time = -1.0;
    vec2 m_last_click_pos{0.f};
};

}  // namespace pv::ui
