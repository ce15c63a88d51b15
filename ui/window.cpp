// ui/window.cpp: window, GL context and ImGui set-up and teardown (see window.h).
#include "window.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "core/base/error.h"

namespace pv::ui {
namespace {
std::string g_glfw_error;
}  // namespace

Window::Glfw::Glfw() {
    glfwSetErrorCallback([](int, const char* message) { g_glfw_error = message; });
    if (!glfwInit())
        throw Error("no display: cannot open a window (" + g_glfw_error +
                    "); the viewer needs X11 or Wayland; `pathview render` works headless");
}

Window::Glfw::~Glfw() { glfwTerminate(); }

struct Window::ImGuiSession {
    explicit ImGuiSession(GLFWwindow* window) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the user's folder
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains to the callbacks installed before
        ImGui_ImplOpenGL3_Init("#version 330 core");
    }
    ~ImGuiSession() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
};

Window::Window(int width, int height, const std::string& title, InputQueue* input) {
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    m_window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!m_window) throw Error("cannot create an OpenGL 3.3 core window: " + g_glfw_error);
    glfwMakeContextCurrent(m_window);
    glfwSwapInterval(1);
    install_callbacks(m_window, input);
    m_imgui = std::make_unique<ImGuiSession>(m_window);
    if (const GLFWvidmode* mode = glfwGetVideoMode(glfwGetPrimaryMonitor()); mode && mode->refreshRate > 0)
        m_refresh_hz = mode->refreshRate;
}

Window::~Window() {
    m_imgui.reset();
    glfwDestroyWindow(m_window);
}

void Window::loading_frame(double seconds) {
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(m_window, &fb_w, &fb_h);
    glViewport(0, 0, fb_w, fb_h);
    glClearColor(0.08f, 0.08f, 0.08f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT);
    new_imgui_frame();
    ImGui::SetNextWindowPos(ImVec2(16.f, 16.f));
    ImGui::Begin("pathview", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_NoSavedSettings);
    ImGui::Text("loading the scene and building its BVH ... %.1f s", seconds);
    ImGui::End();
    render_imgui_and_swap();
    glfwWaitEventsTimeout(0.1);  // redraw the elapsed time; the load's end wakes it at once
}

float Window::framebuffer_scale() const {
    int fb_w = 0, fb_h = 0, win_w = 0, win_h = 0;
    glfwGetFramebufferSize(m_window, &fb_w, &fb_h);
    glfwGetWindowSize(m_window, &win_w, &win_h);
    return win_w > 0 ? float(fb_w) / float(win_w) : 1.f;
}

void Window::new_imgui_frame() {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
}

void Window::render_imgui_and_swap() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glfwSwapBuffers(m_window);
}

}  // namespace pv::ui
