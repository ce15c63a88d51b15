// ui/input.h: input events gathered by GLFW callbacks until the frame handles them. The callbacks are installed
// before ImGui's GLFW backend, which chains to them; the frame then routes each event to ImGui or the scene.
#pragma once

#include <GLFW/glfw3.h>

#include <string>
#include <utility>
#include <vector>

#include "core/base/math.h"

namespace pv::ui {

struct InputQueue {
    struct Button {
        int button, action, mods;
        vec2 pos;     // window pixels
        double time;  // glfwGetTime()
    };
    std::vector<Button> buttons;
    std::vector<std::pair<int, int>> keys;  // presses: key, mods
    bool fly_down[6] = {};                  // W A S D Q E, pressed without Ctrl/Alt/Super (Ctrl+S is no fly key)
    float scroll = 0.f;
    std::vector<std::string> dropped;  // files dropped on the window (drop.h)
    bool any = false;                  // something happened: draw a frame
    bool urgent = false;               // a press, scroll, drop or drag: draw it without waiting a whole refresh
    double first_event = -1.0;         // glfwGetTime() of the first event not yet handled (for the latency figure)
    void note(bool urgent_event = false) {
        any = true;
        urgent = urgent || urgent_event;
        if (first_event < 0.0) first_event = glfwGetTime();
    }
};

// Points the window's user pointer at `queue` and installs the callbacks that fill it.
void install_callbacks(GLFWwindow* window, InputQueue* queue);

}  // namespace pv::ui
