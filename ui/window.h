// ui/window.h: the viewer's window: GLFW, one window with an OpenGL 3.3 core context (vsync), the input callbacks
// (input.h), then the ImGui context with its GLFW and OpenGL3 backends; torn down in reverse order. Also the
// loading screen shown until the first scene is ready. Throws pv::Error when there is no display or no context.
#pragma once

#include <memory>
#include <string>

#include "input.h"

namespace pv::ui {

class Window {
public:
    // A window of width x height window pixels whose input goes to `input` (it must outlive the window).
    Window(int width, int height, const std::string& title, InputQueue* input);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    GLFWwindow* get() const { return m_window; }
    // The primary monitor's refresh rate (60 when unknown).
    double refresh_hz() const { return m_refresh_hz; }
    // Framebuffer pixels per window pixel (1 when the window has no size).
    float framebuffer_scale() const;
    // One frame of the loading screen ("loading the scene ... 1.2 s"), then a wait of at most 0.1 s for an event.
    void loading_frame(double seconds);
    // Starts an ImGui frame (step 2 of the loop) / renders ImGui over the frame and swaps (step 6).
    void new_imgui_frame();
    void render_imgui_and_swap();

private:
    struct Glfw {  // glfwInit .. glfwTerminate
        Glfw();
        ~Glfw();
    };
    struct ImGuiSession;
    Glfw m_glfw;
    GLFWwindow* m_window = nullptr;
    std::unique_ptr<ImGuiSession> m_imgui;
    double m_refresh_hz = 60.0;
};

}  // namespace pv::ui
