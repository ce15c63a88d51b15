// ui/viewer.cpp: the main loop, after Dear ImGui's example: 1 wait for input or a published pass (capped at the
// display rate; sleep while minimised), 2 new ImGui frame and the panel, 3 camera input where ImGui does not
// want it, 4 restart on a change, 5 snapshot -> texture -> display pass, 6 ImGui on top, swap.
// Each step calls into a room that owns one concern and needs no window: navigation.h (gestures -> camera),
// refinement.h (1/4 -> 1/2 -> full resolution, deferral, latency), scene_loader.h (loads off the UI thread),
// snapshot_saver.h (EXR snapshots), panel.h (the ImGui panel), display.h (the GL display pass).
#include "viewer.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <filesystem>

#include "camera_controller.h"
#include "core/environment.h"
#include "core/error.h"
#include "core/scene_file.h"
#include "display.h"
#include "frame_stats.h"
#include "input.h"
#include "navigation.h"
#include "panel.h"
#include "refinement.h"
#include "scene_loader.h"
#include "snapshot_saver.h"
#include "view_log.h"

namespace pv::ui {
namespace {

constexpr float kPanelWidth = 380.f;  // window pixels

std::string g_glfw_error;

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

}  // namespace

class Viewer {
public:
    explicit Viewer(const ViewerOptions& o);
    ~Viewer();
    int run();

private:
    bool wait_for_work();
    NavigationFrame navigation_frame(double dt) const;
    void restart_on_change(const PanelActions& act, bool camera_moved, bool resized, double now);
    void post(const RefinementSchedule::Restart& restart, bool with_materials, bool with_environment, double now);
    // Renders `loaded.scene` from now on with its renderer (the old one is joined): its camera, materials,
    // environment and bookmarks.
    void use_scene(LoadedScene loaded);
    // Loads the scene of the command line in the background while the window shows a loading screen.
    LoadedScene load_first_scene();
    // Adopts a finished background load (the panel's "Load"); on failure the panel shows the error and the
    // current scene stays.
    void poll_loading(double now);
    // Jumps to a bookmark or saves the current camera as one (in the scene file).
    void handle_bookmarks(PanelActions& act);
    void poll_saves();
    void save();
    void log_frames_shown(double end);

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
    SceneLoader m_loader{[] { glfwPostEmptyEvent(); }};
    Panel m_panel{m_log};
    Navigation m_navigation{m_log};
    RefinementSchedule m_schedule;
    FrameStats m_frame_stats;
    ViewState m_state;
    std::vector<std::string> m_warnings;
    bool m_environment_lit = false;

    Snapshot m_shown, m_incoming;
    ConvergenceHistory m_history;
    uint64_t m_history_generation = 0;

    int m_full_w = 0, m_full_h = 0;  // image region, framebuffer pixels
    float m_fb_scale = 1.f;          // framebuffer pixels per window pixel
    double m_refresh_hz = 60.0;
    double m_last_frame = -1.0;
    int m_settle_frames = 0;
    bool m_minimised = false;
    bool m_denoising = false;  // the driver's denoising, as last set from m_state.display.denoise
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
    use_scene(std::move(first));
    m_log.line("start scene=%s triangles=%zu threads=%d gl=\"%s\" refresh_hz=%.0f", m_scene->source.c_str(),
               m_scene->triangle_count(), m_renderer->threads(),
               reinterpret_cast<const char*>(glGetString(GL_RENDERER)), m_refresh_hz);
}

LoadedScene Viewer::load_first_scene() {
    // The window says what it is doing meanwhile and stays responsive.
    const double start = glfwGetTime();
    m_loader.start(m_opt.load_scene, m_opt.threads);
    while (!m_loader.ready()) {
        int fb_w = 0, fb_h = 0;
        glfwGetFramebufferSize(m_window, &fb_w, &fb_h);
        glViewport(0, 0, fb_w, fb_h);
        glClearColor(0.08f, 0.08f, 0.08f, 1.f);
        glClear(GL_COLOR_BUFFER_BIT);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(16.f, 16.f));
        ImGui::Begin("pathview", nullptr,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                         ImGuiWindowFlags_NoSavedSettings);
        ImGui::Text("loading the scene and building its BVH ... %.1f s", glfwGetTime() - start);
        ImGui::End();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        glfwSwapBuffers(m_window);
        glfwWaitEventsTimeout(0.1);  // redraw the elapsed time; the load's end wakes it at once
    }
    m_input = InputQueue{};  // input given to the loading screen does not move the camera afterwards,
    m_input.any = true;      // but the first frame is drawn at once
    return m_loader.take();  // a load error propagates: one line naming the file, and a non-zero exit
}

void Viewer::use_scene(LoadedScene loaded) {
    loaded.renderer->set_on_publish([] { glfwPostEmptyEvent(); });
    loaded.renderer->set_paused(m_state.paused);
    loaded.renderer->set_denoise(m_denoising);
    loaded.renderer->set_target(uint32_t(m_state.target_spp), double(m_state.target_seconds));
    m_renderer = std::move(loaded.renderer);
    m_scene = std::move(loaded.scene);
    vec3 lo, hi;
    m_scene->bounds(lo, hi);
    m_camera = std::make_unique<CameraController>(m_scene->camera, lo, hi);
    m_state.materials = m_scene->materials;
    m_state.selected_material = -1;
    m_environment_lit = environment_emits(*m_scene, m_scene->environment);
    m_state.environment = m_scene->environment;
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
    m_schedule.reset();
    const std::string title = "pathview - " + std::filesystem::path(m_scene->source).filename().string();
    glfwSetWindowTitle(m_window, title.c_str());
}

void Viewer::poll_loading(double now) {
    if (!m_loader.ready()) return;
    m_state.scene_loading = false;
    const std::string path = m_state.scene_path;
    try {
        use_scene(m_loader.take());
    } catch (const std::exception& e) {
        m_state.scene_status = e.what();
        m_state.scene_ok = false;
        m_log.line("scene-error %s", e.what());
        return;
    }
    m_state.scene_status = "loaded " + path;
    m_state.scene_ok = true;
    m_log.line("scene path=%s triangles=%zu", path.c_str(), m_scene->triangle_count());
    post(m_schedule.coarse("scene", now), false, false, now);
}

Viewer::~Viewer() {
    // A background load ends first (it may still post an event to the window).
    m_loader.wait();
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
    if (!continuous && !m_input.any) glfwWaitEventsTimeout(m_schedule.wait_timeout(glfwGetTime(), 0.5));
    const double next = m_last_frame + 1.0 / m_refresh_hz;
    for (double now = glfwGetTime(); now < next; now = glfwGetTime()) glfwWaitEventsTimeout(next - now);
    glfwPollEvents();

    bool work = continuous || m_input.any || m_schedule.deferral_expired(glfwGetTime());
    if (m_renderer->latest(m_incoming) && m_incoming.generation >= m_shown.generation) {
        std::swap(m_shown, m_incoming);
        m_incoming.serial = m_shown.serial;  // latest() copies only what is newer than this
        m_display->upload(m_shown, m_state.display.denoise);
        if (m_shown.generation != m_history_generation) {
            m_history.clear();
            m_history_generation = m_shown.generation;
        }
        m_history.add(m_shown.spp, m_shown.seconds, m_shown.rel_mse);
        work = true;
    }
    if (std::optional<PartialRender> part = m_renderer->take_partial()) {
        const uint32_t spp = uint32_t(part->sample_count());
        const std::string path = m_saver->save_partial(std::move(*part));
        m_state.snapshot_status = "saving " + path + " (resumable)";
        m_log.line("snapshot-start path=%s spp=%u resumable=1", path.c_str(), spp);
        work = true;
    }
    if (m_saver->in_flight()) {
        poll_saves();
        work = work || !m_saver->in_flight();
    }
    return work;
}

int Viewer::run() {
    while (!glfwWindowShouldClose(m_window)) {
        // 1. Wait for something to show.
        const bool work = wait_for_work();
        m_frame_stats.log_if_due(m_log, m_shown);
        if (!work) continue;
        const double start = glfwGetTime();
        m_frame_stats.begin_frame();
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
        facts.level = m_schedule.level();
        facts.frame_ms = m_frame_stats.last_ms();
        PanelActions act = m_panel.draw(m_state, *m_camera, facts, kPanelWidth);
        if (m_state.display.denoise != m_denoising) {  // a display change: the accumulation is not restarted
            m_denoising = m_state.display.denoise;
            m_renderer->set_denoise(m_denoising);
            m_display->upload(m_shown, m_denoising);
            m_log.line("denoise %d", int(m_denoising));
        }

        // 3. Camera and shortcuts where ImGui does not want the mouse or keyboard; scene loads, bookmarks, saves.
        const NavigationResult nav = m_navigation.handle(m_input, navigation_frame(dt), *m_camera, m_state, act);
        if (nav.quit) glfwSetWindowShouldClose(m_window, GLFW_TRUE);
        if (act.save) save();
        if (act.save_resumable) {
            m_renderer->request_partial();
            m_state.snapshot_status = "preparing a resumable snapshot";
            m_state.snapshot_ok = true;
        }
        if (act.load_scene &&
            m_loader.start([path = m_state.scene_path] { return pv::load_scene(path); }, m_opt.threads)) {
            m_state.scene_loading = true;
            m_state.scene_status = "loading " + m_state.scene_path + " ...";
            m_state.scene_ok = true;
            m_log.line("scene-loading path=%s", m_state.scene_path.c_str());
        }
        poll_loading(start);
        handle_bookmarks(act);

        // 4. Restart the accumulation on a change (a new image size included), or refine at rest.
        const int region_w = std::max(fb_w - panel_fb, 1);
        bool resized = false;
        if (region_w != m_full_w || fb_h != m_full_h) {
            const bool first = m_full_w == 0;
            m_full_w = region_w;
            m_full_h = fb_h;
            if (first)
                post(m_schedule.coarse("initial", start), false, false, start);
            else
                resized = true;
        }
        restart_on_change(act, nav.camera_moved, resized, start);

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
        m_frame_stats.end_frame((end - start) * 1e3);
        log_frames_shown(end);
        m_input.any = false;
        m_input.first_event = -1.0;
    }
    m_log.line("exit frames=%d", m_frame_stats.total_frames());
    return 0;
}

NavigationFrame Viewer::navigation_frame(double dt) const {
    NavigationFrame f;
    double cx, cy;
    glfwGetCursorPos(m_window, &cx, &cy);
    f.cursor = vec2(float(cx), float(cy));
    f.image_size = vec2(float(m_full_w), float(m_full_h)) / m_fb_scale;
    glfwGetWindowSize(m_window, nullptr, &f.window_height);
    f.imgui_wants_mouse = ImGui::GetIO().WantCaptureMouse;
    f.imgui_wants_keyboard = ImGui::GetIO().WantCaptureKeyboard;
    f.dt = dt;
    f.pick = [this](vec2 window_pos) {
        return m_renderer->pick(m_camera->desc(), m_full_w, m_full_h, window_pos * m_fb_scale);
    };
    return f;
}

void Viewer::restart_on_change(const PanelActions& act, bool camera_moved, bool resized, double now) {
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
    if (act.environment_changed) m_environment_lit = environment_emits(*m_scene, m_state.environment);
    if (act.materials_changed || act.environment_changed)
        m_warnings = scene_warnings(*m_scene, m_state.materials, m_environment_lit);
    const double since = m_input.first_event >= 0.0 ? std::min(now, m_input.first_event) : now;
    if (const auto restart = m_schedule.update(reason, now, since, m_shown.generation, m_shown.spp))
        post(*restart, act.materials_changed, act.environment_changed, now);
}

void Viewer::post(const RefinementSchedule::Restart& restart, bool with_materials, bool with_environment, double now) {
    RenderRequest req;
    if (with_environment) req.environment = m_state.environment;
    req.camera = m_camera->desc();
    req.settings = m_state.settings;
    req.adaptive = m_state.adaptive;
    req.width = std::max(1, m_full_w / m_schedule.level());
    req.height = std::max(1, m_full_h / m_schedule.level());
    if (with_materials) req.materials = m_state.materials;
    uint64_t generation = 0;
    try {
        generation = m_renderer->restart(req);
    } catch (const Error& e) {
        m_log.line("restart-error %s", e.what());
        return;
    }
    m_schedule.posted(generation, restart, now);
    m_log.line("restart gen=%llu reason=%s size=%dx%d level=%d %s", (unsigned long long)generation,
               restart.reason.c_str(), req.width, req.height, m_schedule.level(), req.settings.describe().c_str());
}

void Viewer::log_frames_shown(double end) {
    for (const RefinementSchedule::PendingFrame& p : m_schedule.shown(m_shown.generation))
        m_log.line("frame gen=%llu shown_gen=%llu latency_ms=%.1f reason=%s size=%dx%d spp=%u",
                   (unsigned long long)p.generation, (unsigned long long)m_shown.generation, (end - p.since) * 1e3,
                   p.reason.c_str(), m_shown.width, m_shown.height, m_shown.spp);
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

int run_viewer(const ViewerOptions& options) {
    Viewer viewer(options);
    return viewer.run();
}

}  // namespace pv::ui
