// ui/viewer.cpp: the main loop, after Dear ImGui's example: 1 wait for input or a published pass (capped at the
// display rate; sleep while minimised), 2 new ImGui frame and the panel, 3 camera input where ImGui does not
// want it, 4 restart on a change, 5 snapshot -> texture -> display pass, 6 ImGui on top, swap.
// Any change restarts at 1/4 resolution; at rest the accumulation is refined to 1/2, then full resolution.
#include "viewer.h"

#include "camera_controller.h"
#include "display.h"
#include "input.h"
#include "panel.h"
#include "snapshot_saver.h"
#include "view_log.h"

#include "core/environment.h"
#include "core/error.h"
#include "core/scene_file.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <chrono>
#include <ctime>
#include <deque>
#include <filesystem>
#include <future>

namespace pv::ui {
namespace {

constexpr float kPanelWidth = 380.f;     // window pixels
constexpr int kCoarsestLevel = 4;        // resolution divisor right after a change
constexpr double kRestSeconds = 0.12;    // no change for this long: refine one level
constexpr double kMaxDeferSeconds = 1.0; // a camera move waits at most this long for the coarse pass in flight
constexpr double kDoubleClickSeconds = 0.35;
constexpr float kClickSlopPx = 3.f;      // a press that moves less than this is a click, not a drag

std::string g_glfw_error;

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// Scene-level warnings: the loader's, plus "no emitters" when no triangle emits and the environment is black.
std::vector<std::string> scene_warnings(const Scene& scene, const std::vector<Material>& materials,
                                        bool environment_lit) {
    std::vector<std::string> out = scene.warnings;
    bool lit = environment_lit;
    for (uint32_t id : scene.material_ids) lit = lit || (id < materials.size() && materials[id].has_emission());
    if (!lit) out.push_back("no emitters and a black environment: the image will be black");
    return out;
}

struct GlfwSession {
    GlfwSession() {
        glfwSetErrorCallback([](int, const char* message) { g_glfw_error = message; });
        if (!glfwInit())
            throw Error("no display: cannot open a window (" + g_glfw_error +
                        "); the viewer needs X11 or Wayland; `pathview render` works headless");
    }
    ~GlfwSession() { glfwTerminate(); }
};

struct ImGuiSession {
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

struct Drag {
    bool active = false, moved = false, pan = false;
    int button = 0;
    vec2 start{0.f}, last{0.f};
};

// A restart waiting for its first frame on screen (for the latency figure in the log).
struct PendingFrame {
    uint64_t generation;
    double since;
    std::string reason;
};

}  // namespace

class Viewer {
public:
    explicit Viewer(const ViewerOptions& o);
    ~Viewer();
    int run();

private:
    bool wait_for_work();
    void handle_scene_input(PanelActions& act, bool& camera_moved, double dt);
    void click(vec2 pos, double time, bool& camera_moved);
    std::optional<PickResult> pick(vec2 window_pos) const;
    void update_request(const PanelActions& act, bool camera_moved, bool resized, double now);
    void post(const std::string& reason, bool with_materials, double now, double since, bool with_environment = false);
    // Renders `scene` from now on with `renderer` (built for it; the old one is joined): its camera, materials,
    // environment and bookmarks.
    void use_scene(std::shared_ptr<const Scene> scene, std::unique_ptr<ProgressiveRenderer> renderer);
    struct LoadedScene;
    // Loads a scene and builds its renderer (the BVH) on another thread; wakes the UI loop when it ends.
    static std::future<LoadedScene> load_async(std::function<Scene()> load, int threads);
    // Loads the scene of the command line in the background while the window shows a loading screen.
    LoadedScene load_first_scene();
    // Starts loading the scene the panel names in the background (parse and BVH build off the UI thread, so the
    // window stays responsive and the current scene keeps rendering).
    void load_scene(double now);
    // Adopts a finished background load; on failure the panel shows the error and the current scene stays.
    void poll_loading(double now);
    // Jumps to a bookmark or saves the current camera as one (in the scene file).
    void handle_bookmarks(PanelActions& act);
    void poll_saves();
    void save();
    void log_stats(double now);

    const ViewerOptions& m_opt;
    ViewLog m_log;
    GlfwSession m_glfw;
    std::shared_ptr<const Scene> m_scene;
    GLFWwindow* m_window = nullptr;
    InputQueue m_input;
    std::unique_ptr<ImGuiSession> m_imgui;
    std::unique_ptr<DisplayPass> m_display;
    std::unique_ptr<ProgressiveRenderer> m_renderer;
    std::unique_ptr<SnapshotSaver> m_saver;
    std::unique_ptr<CameraController> m_camera;
    struct LoadedScene {
        std::shared_ptr<const Scene> scene;
        std::unique_ptr<ProgressiveRenderer> renderer;
    };
    std::future<LoadedScene> m_loading;
    Panel m_panel{m_log};
    ViewState m_state;
    std::vector<std::string> m_warnings;
    bool m_environment_lit = false;

    Snapshot m_shown, m_incoming;
    ConvergenceHistory m_history;
    uint64_t m_history_generation = 0;
    std::deque<PendingFrame> m_pending_frames;

    int m_full_w = 0, m_full_h = 0;  // image region, framebuffer pixels
    float m_fb_scale = 1.f;          // framebuffer pixels per window pixel
    int m_level = kCoarsestLevel;
    uint64_t m_posted = 0;
    double m_last_change = 0.0;
    bool m_deferred = false;         // a camera move waits for the coarse pass in flight
    double m_deferred_since = 0.0;   // its first input event
    double m_refresh_hz = 60.0;
    double m_last_frame = -1.0;
    int m_settle_frames = 0;
    bool m_minimised = false;
    Drag m_drag;
    double m_last_click_time = -1.0;
    vec2 m_last_click_pos{0.f};

    // Timing for the once-a-second log line.
    double m_stats_since = 0.0;
    int m_frames = 0, m_frames_total = 0;
    double m_frame_ms_sum = 0.0, m_frame_ms_max = 0.0, m_frame_ms_last = 0.0;
    double m_frame_cpu_ms_sum = 0.0;  // CPU time of the UI thread (Mesa's llvmpipe threads not included)
};

Viewer::Viewer(const ViewerOptions& o) : m_opt(o), m_log(o.log_file) {
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    m_window = glfwCreateWindow(o.width + int(kPanelWidth), o.height, "pathview - loading", nullptr, nullptr);
    if (!m_window) throw Error("cannot create an OpenGL 3.3 core window: " + g_glfw_error);
    glfwMakeContextCurrent(m_window);
    glfwSwapInterval(1);
    install_callbacks(m_window, &m_input);
    m_imgui = std::make_unique<ImGuiSession>(m_window);
    m_display = std::make_unique<DisplayPass>();
    if (const GLFWvidmode* mode = glfwGetVideoMode(glfwGetPrimaryMonitor()); mode && mode->refreshRate > 0)
        m_refresh_hz = mode->refreshRate;

    LoadedScene first = load_first_scene();
    m_saver = std::make_unique<SnapshotSaver>(o.snapshot_dir, [] { glfwPostEmptyEvent(); });
    m_state.settings = o.settings;
    m_state.adaptive = o.adaptive;
    m_state.snapshot_dir = o.snapshot_dir;
    m_state.scene_path = first.scene->source;
    use_scene(std::move(first.scene), std::move(first.renderer));
    m_log.line("start scene=%s triangles=%zu threads=%d gl=\"%s\" refresh_hz=%.0f", m_scene->source.c_str(),
               m_scene->triangle_count(), m_renderer->threads(),
               reinterpret_cast<const char*>(glGetString(GL_RENDERER)), m_refresh_hz);
}

std::future<Viewer::LoadedScene> Viewer::load_async(std::function<Scene()> load, int threads) {
    return std::async(std::launch::async, [load = std::move(load), threads] {
        struct Wake {  // wakes the UI loop when the load ends, also by an exception
            ~Wake() { glfwPostEmptyEvent(); }
        } wake;
        LoadedScene loaded;
        loaded.scene = std::make_shared<const Scene>(load());
        loaded.renderer = std::make_unique<ProgressiveRenderer>(loaded.scene, threads);  // builds the BVH
        return loaded;
    });
}

Viewer::LoadedScene Viewer::load_first_scene() {
    // Parse and BVH build on another thread; the window says what it is doing meanwhile and stays responsive.
    const double start = glfwGetTime();
    std::future<LoadedScene> loading = load_async(m_opt.load_scene, m_opt.threads);
    while (loading.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
        int fb_w = 0, fb_h = 0;
        glfwGetFramebufferSize(m_window, &fb_w, &fb_h);
        glViewport(0, 0, fb_w, fb_h);
        glClearColor(0.08f, 0.08f, 0.08f, 1.f);
        glClear(GL_COLOR_BUFFER_BIT);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(16.f, 16.f));
        ImGui::Begin("pathview", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                                               ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings);
        ImGui::Text("loading the scene and building its BVH ... %.1f s", glfwGetTime() - start);
        ImGui::End();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        glfwSwapBuffers(m_window);
        glfwWaitEventsTimeout(0.1);  // redraw the elapsed time; the load's end wakes it at once
    }
    m_input = InputQueue{};  // input given to the loading screen does not move the camera afterwards,
    m_input.any = true;      // but the first frame is drawn at once
    return loading.get();    // a load error propagates: one line naming the file, and a non-zero exit
}

void Viewer::use_scene(std::shared_ptr<const Scene> scene, std::unique_ptr<ProgressiveRenderer> renderer) {
    renderer->set_on_publish([] { glfwPostEmptyEvent(); });
    renderer->set_paused(m_state.paused);
    renderer->set_target(uint32_t(m_state.target_spp), double(m_state.target_seconds));
    m_renderer = std::move(renderer);
    m_scene = std::move(scene);
    vec3 lo, hi;
    m_scene->bounds(lo, hi);
    m_camera = std::make_unique<CameraController>(m_scene->camera, lo, hi);
    m_state.materials = m_scene->materials;
    m_state.selected_material = -1;
    m_environment_lit = environment_emits(*m_scene, environment_settings(*m_scene));
    m_state.environment = environment_settings(*m_scene);
    m_state.has_environment_map = m_scene->environment_map != kNoIndex;
    m_state.bookmarks = m_scene->bookmarks;
    m_state.bookmark_status.clear();
    m_warnings = scene_warnings(*m_scene, m_state.materials, m_environment_lit);
    for (const std::string& w : m_warnings) m_log.line("warning %s", w.c_str());
    // Generations restart at 1 with the new renderer: forget everything about the old one.
    m_shown = Snapshot{};
    m_incoming = Snapshot{};
    m_history.clear();
    m_history_generation = 0;
    m_pending_frames.clear();
    m_posted = 0;
    m_deferred = false;
    const std::string title = "pathview - " + std::filesystem::path(m_scene->source).filename().string();
    glfwSetWindowTitle(m_window, title.c_str());
}

void Viewer::load_scene(double) {
    if (m_loading.valid()) return;
    const std::string path = m_state.scene_path;
    const int threads = m_opt.threads;
    m_state.scene_loading = true;
    m_state.scene_status = "loading " + path + " ...";
    m_state.scene_ok = true;
    m_log.line("scene-loading path=%s", path.c_str());
    m_loading = load_async([path] { return pv::load_scene(path); }, threads);
}

void Viewer::poll_loading(double now) {
    if (!m_loading.valid() || m_loading.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    m_state.scene_loading = false;
    const std::string path = m_state.scene_path;
    try {
        LoadedScene loaded = m_loading.get();
        use_scene(std::move(loaded.scene), std::move(loaded.renderer));
    } catch (const std::exception& e) {
        m_state.scene_status = e.what();
        m_state.scene_ok = false;
        m_log.line("scene-error %s", e.what());
        return;
    }
    m_state.scene_status = "loaded " + path;
    m_state.scene_ok = true;
    m_log.line("scene path=%s triangles=%zu", path.c_str(), m_scene->triangle_count());
    m_level = kCoarsestLevel;
    post("scene", false, now, now);
}

Viewer::~Viewer() {
    // A background load ends first (it may still post an event to the window).
    if (m_loading.valid()) m_loading.wait();
    // Reverse order of set-up: writes and render threads end before the GL context and the window go.
    m_saver.reset();
    m_renderer.reset();
    m_display.reset();
    m_imgui.reset();
    if (m_window) glfwDestroyWindow(m_window);
}

bool Viewer::wait_for_work() {
    // Minimised: pause rendering and sleep until the window comes back.
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(m_window, &fb_w, &fb_h);
    if (glfwGetWindowAttrib(m_window, GLFW_ICONIFIED) || fb_w == 0 || fb_h == 0) {
        if (!m_minimised) {
            m_minimised = true;
            m_renderer->set_paused(true);
            m_log.line("minimised: paused");
        }
        glfwWaitEvents();
        m_input.first_event = -1.0;
        return false;
    }
    if (m_minimised) {
        m_minimised = false;
        m_renderer->set_paused(m_state.paused);
        m_log.line("restored");
        m_input.any = true;
    }
    // Sleep until input or a published pass (glfwPostEmptyEvent) arrives, unless the camera is in motion;
    // then never sooner than one display refresh after the previous frame.
    bool fly_keys = false;
    for (bool k : m_input.fly_down) fly_keys = fly_keys || (k && !ImGui::GetIO().WantCaptureKeyboard);
    const bool continuous = fly_keys || m_settle_frames > 0;  // held keys send no events
    // A deferred camera move needs a frame when its wait expires, even if nothing else happens.
    const double timeout = m_deferred ? std::max(0.0, m_last_change + kMaxDeferSeconds - glfwGetTime()) : 0.5;
    if (!continuous && !m_input.any) glfwWaitEventsTimeout(timeout);
    const double next = m_last_frame + 1.0 / m_refresh_hz;
    for (double now = glfwGetTime(); now < next; now = glfwGetTime()) glfwWaitEventsTimeout(next - now);
    glfwPollEvents();

    bool work = continuous || m_input.any || (m_deferred && glfwGetTime() >= m_last_change + kMaxDeferSeconds);
    if (m_renderer->latest(m_incoming) && m_incoming.generation >= m_shown.generation) {
        std::swap(m_shown, m_incoming);
        m_incoming.serial = m_shown.serial;  // latest() copies only what is newer than this
        m_display->upload(m_shown);
        if (m_shown.generation != m_history_generation) {
            m_history.clear();
            m_history_generation = m_shown.generation;
        }
        m_history.add(m_shown.spp, m_shown.seconds, m_shown.rel_mse);
        work = true;
    }
    if (m_saver->in_flight()) {
        poll_saves();
        work = work || !m_saver->in_flight();
    }
    return work;
}

int Viewer::run() {
    m_stats_since = m_log.now();
    while (!glfwWindowShouldClose(m_window)) {
        // 1. Wait for something to show.
        const bool work = wait_for_work();
        log_stats(m_log.now());
        if (!work) continue;
        const double start = glfwGetTime();
        const double start_cpu = thread_cpu_seconds();
        const double dt = m_last_frame < 0.0 ? 0.0 : std::min(start - m_last_frame, 0.1);
        m_last_frame = start;
        m_settle_frames = m_input.any ? 2 : std::max(m_settle_frames - 1, 0);
        int fb_w, fb_h, win_w, win_h;
        glfwGetFramebufferSize(m_window, &fb_w, &fb_h);
        glfwGetWindowSize(m_window, &win_w, &win_h);
        m_fb_scale = win_w > 0 ? float(fb_w) / float(win_w) : 1.f;
        const int panel_fb = int(kPanelWidth * m_fb_scale);

        // 2. New ImGui frame; the panel edits m_state and the camera's lens in place.
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        PanelFacts facts;
        facts.snapshot = &m_shown;
        facts.history = &m_history;
        facts.scene_name = std::filesystem::path(m_scene->source).filename().string();
        facts.triangles = m_scene->triangle_count();
        facts.warnings = m_warnings;
        facts.full_width = m_full_w;
        facts.full_height = m_full_h;
        facts.level = m_level;
        facts.frame_ms = m_frame_ms_last;
        PanelActions act = m_panel.draw(m_state, *m_camera, facts, kPanelWidth);

        // 3. Camera and shortcuts, where ImGui does not want the mouse or keyboard.
        bool camera_moved = false;
        handle_scene_input(act, camera_moved, dt);
        if (act.save) save();
        if (act.load_scene) load_scene(start);
        poll_loading(start);
        handle_bookmarks(act);

        // 4. Restart the accumulation on a change (a new image size included).
        const int region_w = std::max(fb_w - panel_fb, 1);
        bool resized = false;
        if (region_w != m_full_w || fb_h != m_full_h) {
            const bool first = m_full_w == 0;
            m_full_w = region_w;
            m_full_h = fb_h;
            if (first) {
                m_level = kCoarsestLevel;
                post("initial", false, start, start);
            } else {
                resized = true;
            }
        }
        update_request(act, camera_moved, resized, start);

        // 5. The accumulation through the display pass, in the image region.
        glViewport(0, 0, fb_w, fb_h);
        glClearColor(0.08f, 0.08f, 0.08f, 1.f);
        glClear(GL_COLOR_BUFFER_BIT);
        m_display->draw(0, 0, m_full_w, m_full_h, m_state.display);

        // 6. The panel on top; swap.
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        glfwSwapBuffers(m_window);

        const double end = glfwGetTime();
        m_frame_cpu_ms_sum += (thread_cpu_seconds() - start_cpu) * 1e3;
        m_frame_ms_last = (end - start) * 1e3;
        m_frame_ms_sum += m_frame_ms_last;
        m_frame_ms_max = std::max(m_frame_ms_max, m_frame_ms_last);
        ++m_frames;
        ++m_frames_total;
        while (!m_pending_frames.empty() && m_pending_frames.front().generation <= m_shown.generation) {
            const PendingFrame& p = m_pending_frames.front();
            m_log.line("frame gen=%llu shown_gen=%llu latency_ms=%.1f reason=%s size=%dx%d spp=%u",
                       (unsigned long long)p.generation, (unsigned long long)m_shown.generation,
                       (end - p.since) * 1e3, p.reason.c_str(), m_shown.width, m_shown.height, m_shown.spp);
            m_pending_frames.pop_front();
        }
        m_input.any = false;
        m_input.first_event = -1.0;
    }
    m_log.line("exit frames=%d", m_frames_total);
    return 0;
}

void Viewer::handle_scene_input(PanelActions& act, bool& camera_moved, double dt) {
    const ImGuiIO& io = ImGui::GetIO();
    double cx, cy;
    glfwGetCursorPos(m_window, &cx, &cy);
    const vec2 cursor{float(cx), float(cy)};
    const float region_w_win = float(m_full_w) / m_fb_scale;
    auto in_image = [&](vec2 p) { return p.x >= 0.f && p.x < region_w_win && p.y >= 0.f && p.y < float(m_full_h) / m_fb_scale; };
    int win_h;
    glfwGetWindowSize(m_window, nullptr, &win_h);

    // Drags: orbit (left), pan (middle, or shift+left); a press that barely moves is a click.
    auto drag_to = [&](vec2 p) {
        if (glm::length(p - m_drag.start) > kClickSlopPx) m_drag.moved = true;
        const vec2 d = p - m_drag.last;
        m_drag.last = p;
        if (!m_drag.moved || (d.x == 0.f && d.y == 0.f)) return;
        if (m_drag.pan)
            m_camera->pan(d, win_h);
        else
            m_camera->orbit(d);
        camera_moved = true;
    };
    for (const InputQueue::Button& e : m_input.buttons) {
        const bool usable = e.button == GLFW_MOUSE_BUTTON_LEFT || e.button == GLFW_MOUSE_BUTTON_MIDDLE;
        if (e.action == GLFW_PRESS && usable && !m_drag.active && !io.WantCaptureMouse && in_image(e.pos)) {
            m_drag = Drag{};
            m_drag.active = true;
            m_drag.button = e.button;
            m_drag.pan = e.button == GLFW_MOUSE_BUTTON_MIDDLE || (e.mods & GLFW_MOD_SHIFT);
            m_drag.start = m_drag.last = e.pos;
        } else if (e.action == GLFW_RELEASE && m_drag.active && e.button == m_drag.button) {
            drag_to(e.pos);
            m_drag.active = false;
            if (!m_drag.moved && e.button == GLFW_MOUSE_BUTTON_LEFT) click(e.pos, e.time, camera_moved);
        }
    }
    m_input.buttons.clear();
    if (m_drag.active) drag_to(cursor);

    if (m_input.scroll != 0.f && !io.WantCaptureMouse && in_image(cursor)) {
        m_camera->dolly(m_input.scroll);
        camera_moved = true;
    }
    m_input.scroll = 0.f;

    // Shortcuts. Ctrl+S and Ctrl+Q work everywhere; the rest only when ImGui is not typing.
    for (const auto& [key, mods] : m_input.keys) {
        const bool ctrl = (mods & GLFW_MOD_CONTROL) != 0;
        if (ctrl && key == GLFW_KEY_S) act.save = true;
        if (ctrl && key == GLFW_KEY_Q) glfwSetWindowShouldClose(m_window, GLFW_TRUE);
        if (ctrl || io.WantCaptureKeyboard) continue;
        if (key == GLFW_KEY_F) act.frame_all = true;
        if (key == GLFW_KEY_R) act.reset_camera = true;
        if (key == GLFW_KEY_P) {
            m_state.paused = !m_state.paused;
            act.control_changed = true;
        }
        if (key == GLFW_KEY_G && in_image(cursor))
            if (const auto hit = pick(cursor)) {
                m_camera->focus_on(hit->position);
                camera_moved = true;
                m_log.line("action focus distance=%g", double(m_camera->desc().focus_distance));
            }
    }
    m_input.keys.clear();
    if (act.frame_all) {
        m_camera->frame_all();
        m_log.line("action frame-all");
    }
    if (act.reset_camera) {
        m_camera->reset();
        m_log.line("action reset-camera");
    }

    // Fly: WASD in the view plane, Q/E down/up, at the panel's speed.
    if (!io.WantCaptureKeyboard) {
        const bool* k = m_input.fly_down;  // W A S D Q E
        auto axis = [](bool plus, bool minus) { return float(plus) - float(minus); };
        const vec3 move(axis(k[3], k[1]), axis(k[5], k[4]), axis(k[0], k[2]));
        if (move != vec3(0.f) && dt > 0.0) {
            m_camera->fly(move, float(dt));
            camera_moved = true;
        }
    }
}

std::optional<PickResult> Viewer::pick(vec2 window_pos) const {
    return m_renderer->pick(m_camera->desc(), m_full_w, m_full_h, window_pos * m_fb_scale);
}

void Viewer::click(vec2 pos, double time, bool& camera_moved) {
    const std::optional<PickResult> hit = pick(pos);
    if (m_state.pick_focus) {
        m_state.pick_focus = false;
        if (hit) {
            m_camera->focus_on(hit->position);
            camera_moved = true;
            m_log.line("action focus distance=%g", double(m_camera->desc().focus_distance));
        }
        return;
    }
    const bool is_double = m_last_click_time >= 0.0 && time - m_last_click_time < kDoubleClickSeconds &&
                           glm::length(pos - m_last_click_pos) <= kClickSlopPx;
    m_last_click_time = is_double ? -1.0 : time;
    m_last_click_pos = pos;
    if (!hit) return;
    if (is_double) {
        m_camera->retarget(hit->position);
        camera_moved = true;
        m_log.line("retarget %g,%g,%g", hit->position.x, hit->position.y, hit->position.z);
    } else {
        m_state.selected_material = int(hit->material);
        m_log.line("select material=%u triangle=%u", hit->material, hit->triangle);
    }
}

void Viewer::update_request(const PanelActions& act, bool camera_moved, bool resized, double now) {
    if (glfwWindowShouldClose(m_window)) return;  // closing: nothing new to render
    if (act.control_changed) {
        m_renderer->set_paused(m_state.paused || m_minimised);
        m_renderer->set_target(uint32_t(m_state.target_spp), double(m_state.target_seconds));
        m_log.line("control paused=%d target_spp=%d target_seconds=%g", int(m_state.paused), m_state.target_spp,
                   double(m_state.target_seconds));
    }
    std::string reason;
    auto add = [&](const char* r) { reason += (reason.empty() ? "" : ",") + std::string(r); };
    if (camera_moved || act.camera_changed || act.frame_all || act.reset_camera) add("camera");
    if (act.settings_changed) add("settings");
    if (act.materials_changed) add("material");
    if (act.environment_changed) add("environment");
    if (resized) add("resize");
    if (act.restart) add("restart");
    const double since = m_input.first_event >= 0.0 ? std::min(now, m_input.first_event) : now;
    // While the camera moves, the coarse pass in flight is not cancelled for the next mouse position: it lands
    // first, so the picture keeps following the mouse even when a pass takes longer than a UI frame.
    const bool waiting = m_shown.generation < m_posted && now - m_last_change < kMaxDeferSeconds;
    if (reason == "camera" && m_level == kCoarsestLevel && waiting) {
        if (!m_deferred) m_deferred_since = since;
        m_deferred = true;
        return;
    }
    if (reason.empty() && m_deferred && !waiting) reason = "camera";
    if (!reason.empty()) {
        if (act.environment_changed)
            m_environment_lit = environment_emits(*m_scene, m_state.environment);
        if (act.materials_changed || act.environment_changed)
            m_warnings = scene_warnings(*m_scene, m_state.materials, m_environment_lit);
        m_level = kCoarsestLevel;
        post(reason, act.materials_changed, now, m_deferred ? std::min(m_deferred_since, since) : since,
             act.environment_changed);
        m_deferred = false;
    } else if (m_level > 1 && now - m_last_change >= kRestSeconds && m_shown.generation == m_posted &&
               m_shown.spp >= 1) {
        m_level /= 2;
        post("refine", false, now, now);
    }
}

void Viewer::post(const std::string& reason, bool with_materials, double now, double since, bool with_environment) {
    RenderRequest req;
    if (with_environment) req.environment = m_state.environment;
    req.camera = m_camera->desc();
    req.settings = m_state.settings;
    req.adaptive = m_state.adaptive;
    req.width = std::max(1, m_full_w / m_level);
    req.height = std::max(1, m_full_h / m_level);
    if (with_materials) req.materials = m_state.materials;
    try {
        m_posted = m_renderer->restart(req);
    } catch (const Error& e) {
        m_log.line("restart-error %s", e.what());
        return;
    }
    m_last_change = now;
    m_pending_frames.push_back({m_posted, since, reason});  // latency from the input event, not from this frame
    m_log.line("restart gen=%llu reason=%s size=%dx%d level=%d %s", (unsigned long long)m_posted, reason.c_str(),
               req.width, req.height, m_level, req.settings.describe().c_str());
}

void Viewer::handle_bookmarks(PanelActions& act) {
    if (act.goto_bookmark >= 0 && size_t(act.goto_bookmark) < m_state.bookmarks.size()) {
        m_camera->desc() = m_state.bookmarks[size_t(act.goto_bookmark)].camera;
        act.camera_changed = true;
        m_log.line("bookmark go name=%s", m_state.bookmarks[size_t(act.goto_bookmark)].name.c_str());
    }
    if (!act.save_bookmark.empty()) {
        try {
            const std::string file = pv::save_bookmark(m_scene->source, act.save_bookmark, m_camera->desc());
            bool replaced = false;
            for (Scene::Bookmark& b : m_state.bookmarks)
                if (b.name == act.save_bookmark) b.camera = m_camera->desc(), replaced = true;
            if (!replaced) m_state.bookmarks.push_back({act.save_bookmark, m_camera->desc()});
            m_state.bookmark_status = "saved '" + act.save_bookmark + "' in " + file;
            m_state.bookmark_ok = true;
            m_log.line("bookmark saved name=%s file=%s", act.save_bookmark.c_str(), file.c_str());
        } catch (const Error& e) {
            m_state.bookmark_status = e.what();
            m_state.bookmark_ok = false;
        }
    }
}

void Viewer::save() {
    if (m_shown.spp == 0) {
        m_state.snapshot_status = "nothing rendered yet";
        m_state.snapshot_ok = false;
        return;
    }
    const std::string path = m_saver->save(m_shown);
    m_state.snapshot_status = "saving " + path;
    m_state.snapshot_ok = true;
    m_log.line("snapshot-start path=%s spp=%u", path.c_str(), m_shown.spp);
}

void Viewer::poll_saves() {
    for (const SaveResult& r : m_saver->finished()) {
        m_state.snapshot_ok = r.ok;
        if (r.ok) {
            m_state.snapshot_status = "saved " + r.path + " (" + std::to_string(r.spp) + " spp)";
            m_log.line("snapshot path=%s spp=%u", r.path.c_str(), r.spp);
        } else {
            m_state.snapshot_status = r.error;
            m_log.line("snapshot-error path=%s error=%s", r.path.c_str(), r.error.c_str());
        }
    }
}

void Viewer::log_stats(double now) {
    if (now - m_stats_since < 1.0) return;
    const Snapshot& s = m_shown;
    m_log.line("stats gen=%llu size=%dx%d spp=%u render_s=%.2f spp_per_s=%.2f mrays_per_s=%.2f ms_per_pass=%.1f "
               "rel_mse=%.3e frames=%d frame_ms_avg=%.2f frame_ms_max=%.2f frame_cpu_ms_avg=%.2f",
               (unsigned long long)s.generation, s.width, s.height, s.spp, s.seconds,
               s.seconds > 0.0 ? s.spp / s.seconds : 0.0, s.mrays_per_s, s.ms_per_pass, s.rel_mse, m_frames,
               m_frames ? m_frame_ms_sum / m_frames : 0.0, m_frame_ms_max,
               m_frames ? m_frame_cpu_ms_sum / m_frames : 0.0);
    m_stats_since = now;
    m_frames = 0;
    m_frame_ms_sum = m_frame_ms_max = m_frame_cpu_ms_sum = 0.0;
}

int run_viewer(const ViewerOptions& options) {
    Viewer viewer(options);
    return viewer.run();
}

}  // namespace pv::ui
