// ui/input.cpp: the GLFW callbacks behind InputQueue.
#include "input.h"

namespace pv::ui {
namespace {

InputQueue& queue_of(GLFWwindow* w) { return *static_cast<InputQueue*>(glfwGetWindowUserPointer(w)); }

constexpr int kFlyKeys[6] = {GLFW_KEY_W, GLFW_KEY_A, GLFW_KEY_S, GLFW_KEY_D, GLFW_KEY_Q, GLFW_KEY_E};

// Tracks the fly keys from their own press and release events: a key counts as held only if it was pressed
// without a command modifier, so a quick Ctrl+S never moves the camera.
void track_fly_key(InputQueue& q, int key, int action, int mods) {
    for (int i = 0; i < 6; ++i)
        if (key == kFlyKeys[i] && action != GLFW_REPEAT)
            q.fly_down[i] = action == GLFW_PRESS && !(mods & (GLFW_MOD_CONTROL | GLFW_MOD_ALT | GLFW_MOD_SUPER));
}

}  // namespace

void install_callbacks(GLFWwindow* window, InputQueue* queue) {
    glfwSetWindowUserPointer(window, queue);
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
        double x, y;
        glfwGetCursorPos(w, &x, &y);
        queue_of(w).buttons.push_back({button, action, mods, vec2(float(x), float(y)), glfwGetTime()});
        queue_of(w).note(true);
    });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
        queue_of(w).scroll += float(dy);
        queue_of(w).note(true);
    });
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int mods) {
        if (action == GLFW_PRESS) queue_of(w).keys.emplace_back(key, mods);
        track_fly_key(queue_of(w), key, action, mods);
        queue_of(w).note(action == GLFW_PRESS);
    });
    glfwSetWindowFocusCallback(window, [](GLFWwindow* w, int focused) {
        if (!focused)
            for (bool& k : queue_of(w).fly_down) k = false;
        queue_of(w).note();
    });
    glfwSetDropCallback(window, [](GLFWwindow* w, int count, const char** paths) {
        for (int i = 0; i < count; ++i)
            if (paths[i]) queue_of(w).dropped.emplace_back(paths[i]);
        queue_of(w).note(true);
    });
    glfwSetCharCallback(window, [](GLFWwindow* w, unsigned) { queue_of(w).note(); });
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double, double) {
        // A drag (any button held) moves the camera or a divider: urgent; hovering is not.
        bool held = false;
        for (int b = GLFW_MOUSE_BUTTON_1; b <= GLFW_MOUSE_BUTTON_3; ++b)
            held = held || glfwGetMouseButton(w, b) == GLFW_PRESS;
        queue_of(w).note(held);
    });
    glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int, int) { queue_of(w).note(); });
    glfwSetWindowRefreshCallback(window, [](GLFWwindow* w) { queue_of(w).note(); });
}

}  // namespace pv::ui
