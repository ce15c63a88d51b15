// ui/navigation.cpp: gestures -> camera (see navigation.h).
#include "navigation.h"

#include <algorithm>
#include <cmath>

namespace pv::ui {

namespace {

bool in_image(const NavigationFrame& frame, vec2 p) {
    return p.x >= 0.f && p.x < frame.image_size.x && p.y >= 0.f && p.y < frame.image_size.y;
}

}  // namespace

NavigationResult Navigation::handle(InputQueue& input, const NavigationFrame& frame, CameraController& camera,
                                    ViewState& state, PanelActions& act) {
    NavigationResult result;
    handle_buttons(input, frame, camera, state, act, result);
    if (input.scroll != 0.f && !frame.imgui_wants_mouse && in_image(frame, frame.cursor)) {
        camera.dolly(input.scroll);
        result.camera_moved = true;
    }
    input.scroll = 0.f;
    handle_keys(input, frame, camera, state, act, result);
    if (act.frame_all) {
        camera.frame_all();
        m_log.line("action frame-all");
    }
    if (act.reset_camera) {
        camera.reset();
        m_log.line("action reset-camera");
    }

    // Fly: WASD in the view plane, Q/E down/up, at the panel's speed.
    if (!frame.imgui_wants_keyboard) {
        const bool* k = input.fly_down;  // W A S D Q E
        auto axis = [](bool plus, bool minus) { return float(plus) - float(minus); };
        const vec3 move(axis(k[3], k[1]), axis(k[5], k[4]), axis(k[0], k[2]));
        if (move != vec3(0.f) && frame.dt > 0.0) {
            camera.fly(move, float(frame.dt));
            result.camera_moved = true;
        }
    }
    return result;
}

// Drags: orbit (left), pan (middle, or shift+left); a press that barely moves is a click.
void Navigation::drag_to(vec2 p, const NavigationFrame& frame, CameraController& camera, PanelActions& act,
                         NavigationResult& result) {
    if (glm::length(p - m_drag.start) > kClickSlopPx) m_drag.moved = true;
    const vec2 d = p - m_drag.last;
    m_drag.last = p;
    if (m_drag.divider) {  // compare view's divider: follows the cursor
        act.compare.divider = std::clamp(p.x / std::max(frame.image_size.x, 1.f), 0.f, 1.f);
        return;
    }
    if (m_drag.region) return;  // the rectangle is taken at the release
    if (!m_drag.moved || (d.x == 0.f && d.y == 0.f)) return;
    if (m_drag.pan)
        camera.pan(d, frame.window_height);
    else
        camera.orbit(d);
    result.camera_moved = true;
}

void Navigation::handle_buttons(InputQueue& input, const NavigationFrame& frame, CameraController& camera,
                                ViewState& state, PanelActions& act, NavigationResult& result) {
    for (const InputQueue::Button& e : input.buttons) {
        const bool usable = e.button == GLFW_MOUSE_BUTTON_LEFT || e.button == GLFW_MOUSE_BUTTON_MIDDLE ||
                            e.button == GLFW_MOUSE_BUTTON_RIGHT;
        if (e.action == GLFW_PRESS && usable && !m_drag.active && !frame.imgui_wants_mouse && in_image(frame, e.pos)) {
            m_drag = Drag{};
            m_drag.active = true;
            m_drag.button = e.button;
            m_drag.pan = e.button == GLFW_MOUSE_BUTTON_MIDDLE || (e.mods & GLFW_MOD_SHIFT);
            m_drag.region = e.button == GLFW_MOUSE_BUTTON_LEFT && (e.mods & GLFW_MOD_CONTROL) && !m_drag.pan;
            m_drag.divider = e.button == GLFW_MOUSE_BUTTON_RIGHT;
            m_drag.start = m_drag.last = e.pos;
            if (m_drag.divider) drag_to(e.pos, frame, camera, act, result);  // a right click puts the divider there
        } else if (e.action == GLFW_RELEASE && m_drag.active && e.button == m_drag.button) {
            drag_to(e.pos, frame, camera, act, result);
            m_drag.active = false;
            if (m_drag.region) {
                if (m_drag.moved) set_region(m_drag.start, e.pos, frame, state, act);
                continue;
            }
            if (!m_drag.moved && e.button == GLFW_MOUSE_BUTTON_LEFT) click(e.pos, e.time, frame, camera, state, result);
        }
    }
    input.buttons.clear();
    if (m_drag.active) drag_to(frame.cursor, frame, camera, act, result);
}

// Shortcuts. Ctrl+S and Ctrl+Q work everywhere; the rest only when ImGui is not typing.
void Navigation::handle_keys(InputQueue& input, const NavigationFrame& frame, CameraController& camera,
                             ViewState& state, PanelActions& act, NavigationResult& result) {
    for (const auto& [key, mods] : input.keys) {
        const bool ctrl = (mods & GLFW_MOD_CONTROL) != 0;
        const bool shift = (mods & GLFW_MOD_SHIFT) != 0;
        if (ctrl && key == GLFW_KEY_S) (shift ? act.save_png : act.save) = true;
        if (ctrl && key == GLFW_KEY_Q) result.quit = true;
        if (ctrl || frame.imgui_wants_keyboard) continue;
        if (key == GLFW_KEY_F) act.frame_all = true;
        if (key == GLFW_KEY_R) act.reset_camera = true;
        if (key == GLFW_KEY_X && state.region) {
            state.region.reset();
            act.region_changed = true;
            m_log.line("action region cleared");
        }
        if (key == GLFW_KEY_N) {
            state.display.denoise = !state.display.denoise;
            m_log.line("action show %s", state.display.denoise ? "denoised" : "raw");
        }
        if (key == GLFW_KEY_T) {
            cycle_view_transform(state.display, state.ocio);
            m_log.line("action view-transform %s", name_of(kViewTransformNames, state.display.transform));
        }
        if (key == GLFW_KEY_B) act.compare.hold = true;
        if (key == GLFW_KEY_C) act.compare.cycle = true;
        if (key == GLFW_KEY_V) act.compare.flip = true;
        if (key == GLFW_KEY_P) {
            state.paused = !state.paused;
            act.control_changed = true;
        }
        if (key == GLFW_KEY_G && in_image(frame, frame.cursor) && frame.pick)
            if (const auto hit = frame.pick(frame.cursor)) {
                camera.focus_on(hit->position);
                result.camera_moved = true;
                m_log.line("action focus distance=%g", double(camera.desc().focus_distance));
            }
    }
    input.keys.clear();
}

void Navigation::set_region(vec2 a, vec2 b, const NavigationFrame& frame, ViewState& state, PanelActions& act) {
    const vec2 render = frame.render_size.x > 0.f ? frame.render_size : frame.image_size;
    const vec2 scale = render / glm::max(frame.image_size, vec2(1.f));
    const vec2 lo = glm::min(a, b) * scale, hi = glm::max(a, b) * scale;
    const int w = int(render.x), h = int(render.y);
    const PixelRect r{std::clamp(int(std::floor(lo.x)), 0, w), std::clamp(int(std::floor(lo.y)), 0, h),
                      std::clamp(int(std::ceil(hi.x)), 0, w), std::clamp(int(std::ceil(hi.y)), 0, h)};
    if (r.empty()) return;
    state.region = r;
    act.region_changed = true;
    m_log.line("action region %s", format_region(r).c_str());
}

void Navigation::click(vec2 pos, double time, const NavigationFrame& frame, CameraController& camera, ViewState& state,
                       NavigationResult& result) {
    const std::optional<PickResult> hit = frame.pick ? frame.pick(pos) : std::nullopt;
    if (state.pick_focus) {
        state.pick_focus = false;
        if (hit) {
            camera.focus_on(hit->position);
            result.camera_moved = true;
            m_log.line("action focus distance=%g", double(camera.desc().focus_distance));
        }
        return;
    }
    const bool is_double = m_last_click_time >= 0.0 && time - m_last_click_time < kDoubleClickSeconds &&
                           glm::length(pos - m_last_click_pos) <= kClickSlopPx;
    m_last_click_time = is_double ? -1.0 : time;
    m_last_click_pos = pos;
    if (!hit) return;
    if (is_double) {
        camera.retarget(hit->position);
        result.camera_moved = true;
        m_log.line("retarget %g,%g,%g", hit->position.x, hit->position.y, hit->position.z);
    } else {
        state.selected_material = int(hit->material);
        m_log.line("select material=%u triangle=%u", hit->material, hit->triangle);
    }
}

}  // namespace pv::ui
