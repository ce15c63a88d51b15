// ui/viewer.cpp: the main loop, after Dear ImGui's example: 1 wait for input or a published pass (frame_pacing.h),
// 2 new ImGui frame and the panel (panel.h), 3 camera input where ImGui does not want it (navigation.h), saves
// (snapshots.h), loads and drops (scene_loads.h), bookmarks, compare (compare_display.h), 4 restart on a change
// (restarts.h, refinement.h), 5 snapshot -> texture -> display pass (shown_image.h, display.h), 6 ImGui on top, swap
// (window.h). Each step calls into a room that owns one concern; only window, display, frame_pacing and
// compare_display need the window. Also here: the scene on screen (active_scene.h) changing, and telemetry.

#include "viewer.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <utility>

#include "active_scene.h"
#include "bookmarks.h"
#include "camera_controller.h"
#include "compare_display.h"
#include "dark_view.h"
#include "display.h"
#include "frame_pacing.h"
#include "frame_stats.h"
#include "navigation.h"
#include "panel.h"
#include "refinement.h"
#include "restarts.h"
#include "scene_loads.h"
#include "shown_image.h"
#include "snapshots.h"
#include "window.h"

namespace pv::ui {
namespace {
constexpr float kPanelWidth = 380.f;  // window pixels
}  // namespace

class Viewer {
public:
    explicit Viewer(const ViewerOptions& o);
    int run();

private:
    bool wait_for_work();
    PanelActions draw_panel();
    NavigationResult handle_input(PanelActions& act, double dt, double now);
    void restart_on_change(const PanelActions& act, bool camera_moved, int region_w, int fb_h, double now);
    void post(const RefinementSchedule::Restart& restart, bool with_materials, bool with_environment, double now);
    // Renders `loaded.scene` from now on with its renderer (the old one is joined).
    void use_scene(LoadedScene loaded);
    // Adopts a finished background load (the panel's "Load", a drop); on failure the current scene stays.
    void poll_loading(double now);
    PanelFacts panel_facts() const;
    bool take_latest();
    void show_first_pass(double frame_start);

    // Members are destroyed in reverse order: loads, writes and render threads end before the GL context goes.
    const ViewerOptions& m_opt;
    ViewLog m_log;
    InputQueue m_input;
    Window m_window;
    std::unique_ptr<DisplayPass> m_display;
    SceneLoader m_loader{[] { glfwPostEmptyEvent(); }};
    Snapshots m_snapshots;
    std::unique_ptr<ProgressiveRenderer> m_renderer;
    std::unique_ptr<CameraController> m_camera;
    ActiveScene m_scene{m_log};
    Panel m_panel{m_log};
    Navigation m_navigation{m_log};
    RefinementSchedule m_schedule;
    ShownImage m_image;
    Compare m_compare;
    CompareDisplay m_compare_display{m_compare, *m_display, m_log};
    SceneLoads m_loads{m_loader, m_scene, m_log, m_opt.threads};
    FramePacing m_pacing;
    FrameStats m_frame_stats;
    mutable DarkView m_dark;  // measured when the panel asks, once per snapshot
    ViewState m_state;

    int m_full_w = 0, m_full_h = 0;  // image region, framebuffer pixels
    float m_fb_scale = 1.f;          // framebuffer pixels per window pixel
    bool m_denoising = false;        // the driver's denoising, as last set from m_state.display.denoise
};

Viewer::Viewer(const ViewerOptions& o)
    : m_opt(o),
      m_log(o.log_file),
      m_window(o.width + int(kPanelWidth), o.height, "pathview - loading", &m_input),
      m_display(std::make_unique<DisplayPass>()),
      m_snapshots(
          o.snapshot_dir, [] { glfwPostEmptyEvent(); }, m_log) {
    // The scene of the command line loads in the background; the window says what it is doing meanwhile.
    LoadedScene first = m_loads.first(o.load_scene, [this](double s) { m_window.loading_frame(s); });
    m_input = InputQueue{};  // input given to the loading screen does not move the camera afterwards,
    m_input.any = true;      // but the first frame is drawn at once
    m_state.settings = o.settings;
    m_state.adaptive = o.adaptive;
    m_state.snapshot_dir = o.snapshot_dir;
    m_state.display.exposure = o.display.exposure;
    m_state.display.transform = o.display.transform;
    m_state.display.ocio = o.display.ocio;
    m_state.ocio.config = o.ocio_config;
    m_state.ocio.input = o.ocio_input;
    m_state.scene_path = first.scene->source;
    m_denoising = m_state.display.denoise;  // denoised by default: the first passes are filtered too
    use_scene(std::move(first));
    if (o.compare_image) m_compare_display.set_b(*o.compare_image, o.compare_path);
    m_log.line("start scene=%s triangles=%zu threads=%d gl=\"%s\" refresh_hz=%.0f", m_scene.scene().source.c_str(),
               m_scene.scene().triangle_count(), m_renderer->threads(),
               reinterpret_cast<const char*>(glGetString(GL_RENDERER)), m_window.refresh_hz());
}

void Viewer::use_scene(LoadedScene loaded) {
    loaded.renderer->set_on_publish([] { glfwPostEmptyEvent(); });
    loaded.renderer->set_denoise(m_denoising);
    apply_controls(*loaded.renderer, m_state, false);
    m_renderer = std::move(loaded.renderer);
    vec3 lo, hi;
    loaded.scene->bounds(lo, hi);
    m_camera = std::make_unique<CameraController>(loaded.scene->camera, lo, hi);
    m_scene.adopt(std::move(loaded.scene), m_state);
    m_image.reset();
    m_schedule.reset();
    glfwSetWindowTitle(m_window.get(), ("pathview - " + m_scene.file_name()).c_str());
}

void Viewer::poll_loading(double now) {
    std::optional<LoadedScene> loaded = m_loads.take_finished(m_state);
    if (!loaded) return;
    use_scene(std::move(*loaded));
    m_loads.adopted(m_state);
    post(m_schedule.coarse("scene", now), false, false, now);
}

PanelFacts Viewer::panel_facts() const {
    PanelFacts facts;
    facts.snapshot = &m_image.shown();
    facts.history = &m_image.history();
    facts.scene_name = m_scene.file_name();
    facts.triangles = m_scene.scene().triangle_count();
    facts.warnings = m_scene.warnings();
    facts.full_width = m_full_w;
    facts.full_height = m_full_h;
    facts.level = m_schedule.level();
    facts.frame_ms = m_frame_stats.last_ms();
    facts.compare = &m_compare;
    facts.compare_camera_moved = m_compare.camera_moved(m_camera->desc());
    facts.dark_view = m_dark.update(m_image.shown(), m_scene.environment_lit());
    facts.dark_mean = m_dark.mean();
    return facts;
}

// Takes the renderer's newest pass, if there is one, onto the screen's textures and the comparison; true if it did.
bool Viewer::take_latest() {
    if (!m_image.update([this](Snapshot& s) { return m_renderer->latest(s); })) return false;
    m_display->upload(m_image.displayed(), m_state.display.denoise);
    m_frame_stats.pass_shown(m_state.display.denoise && !m_image.displayed().denoised.empty() &&
                             m_image.displayed().denoised_spp == m_image.displayed().spp);
    m_compare_display.new_pass(m_image.shown(), m_image.displayed(), m_denoising);
    // The next change restarts at the finest resolution whose first pass is predicted within half a refresh.
    const Snapshot& s = m_image.shown();
    if (m_full_w > 0)
        m_schedule.measured_first_pass(s.first_ready_ms * 1e-3, s.width * s.height, double(m_full_w) * m_full_h,
                                       0.5 / m_window.refresh_hz());
    return true;
}

// A restart posted in this frame: its first pass (sized by RefinementSchedule) is waited for until this refresh ends
// and drawn in this very frame rather than the next; a slower pass is shown by a later frame, as before.
void Viewer::show_first_pass(double frame_start) {
    const double left = frame_start + 1.0 / m_window.refresh_hz() - glfwGetTime();
    if (left <= 0.0) return;
    const auto timeout = std::chrono::milliseconds(std::max(1L, long(left * 1e3)));
    if (m_renderer->wait_for(m_schedule.posted_generation(), 1, timeout)) take_latest();
}

bool Viewer::wait_for_work() {
    auto pause = [this](bool minimised) {
        apply_controls(*m_renderer, m_state, minimised);
        m_log.line(minimised ? "minimised: paused" : "restored");
    };
    if (m_pacing.sleep_while_minimised(m_window.get(), m_input, pause)) return false;  // until it comes back
    // Sleep until input or a published pass (glfwPostEmptyEvent) arrives (frame_pacing.h).
    const bool wants_keyboard = ImGui::GetIO().WantCaptureKeyboard;
    const bool continuous = m_pacing.continuous(m_input, wants_keyboard);
    m_pacing.wait(m_input, wants_keyboard, m_schedule.wait_timeout(glfwGetTime(), 0.5), m_window.refresh_hz(),
                  [this] { return m_renderer->published_generation() > m_image.shown().generation; });

    bool work = continuous || m_input.any || m_schedule.deferral_expired(glfwGetTime());
    if (take_latest()) work = true;
    if (m_snapshots.collect(*m_renderer, m_state)) work = true;
    return work;
}

int Viewer::run() {
    GLFWwindow* window = m_window.get();
    while (!glfwWindowShouldClose(window)) {
        // 1. Wait for something to show.
        const bool work = wait_for_work();
        m_frame_stats.log_if_due(m_log, m_image.shown());
        if (!work) continue;
        const double start = glfwGetTime();
        m_frame_stats.begin_frame();
        const double dt = m_pacing.begin_frame(start, m_input.any);
        int fb_w, fb_h;
        glfwGetFramebufferSize(window, &fb_w, &fb_h);
        m_fb_scale = m_window.framebuffer_scale();

        // 2. New ImGui frame; the panel edits m_state and the camera's lens in place.
        m_window.new_imgui_frame();
        PanelActions act = draw_panel();

        // 3. Camera and shortcuts where ImGui does not want the mouse or keyboard; scene loads, bookmarks, saves.
        const NavigationResult nav = handle_input(act, dt, start);
        if (nav.quit) glfwSetWindowShouldClose(window, GLFW_TRUE);

        // 4. Restart the accumulation on a change (a new image size included), or refine at rest.
        restart_on_change(act, nav.camera_moved, std::max(fb_w - int(kPanelWidth * m_fb_scale), 1), fb_h, start);

        // 5. The accumulation through the display pass, in the image region.
        DisplayPass::clear(fb_w, fb_h);
        m_state.display.compare = m_compare.view();
        m_state.display.divider = m_compare.divider();
        m_display->draw(0, 0, m_full_w, m_full_h, m_state.display);

        // 6. The panel on top; swap.
        m_window.render_imgui_and_swap();
        const double end = glfwGetTime();
        m_frame_stats.end_frame((end - start) * 1e3);
        log_frames_shown(m_log, m_schedule, m_image.shown(), end);
        m_input.any = m_input.urgent = false;
        m_input.first_event = -1.0;
    }
    m_log.line("exit frames=%d", m_frame_stats.total_frames());
    return 0;
}

// Step 2: the panel, the compare overlay, and a denoise toggle (a display change: the accumulation is not restarted).
PanelActions Viewer::draw_panel() {
    const PanelFacts facts = panel_facts();
    PanelActions act = m_panel.draw(m_state, *m_camera, facts, kPanelWidth);
    draw_compare_overlay(m_compare, facts.compare_camera_moved, float(m_full_w) / m_fb_scale,
                         float(m_full_h) / m_fb_scale);
    if (m_state.display.denoise != m_denoising) {
        m_denoising = m_state.display.denoise;
        m_renderer->set_denoise(m_denoising);
        m_display->upload(m_image.displayed(), m_denoising);
        m_compare_display.upload_difference(m_image.displayed(), m_denoising);
        m_log.line("denoise %d", int(m_denoising));
    }
    return act;
}

// Step 3: input to the camera (navigation.h), then saves, loads, drops, bookmarks and the compare views.
NavigationResult Viewer::handle_input(PanelActions& act, double dt, double now) {
    auto pick = [this](vec2 at) { return m_renderer->pick(m_camera->desc(), m_full_w, m_full_h, at * m_fb_scale); };
    const NavigationFrame frame = read_navigation_frame(m_window.get(), vec2(m_full_w, m_full_h), m_fb_scale, dt, pick);
    const NavigationResult nav = m_navigation.handle(m_input, frame, *m_camera, m_state, act);
    m_snapshots.handle(
        act, m_image.shown(), m_state.display.denoise, *m_renderer,
        [this] { return m_display->read_shaded(m_state.display); }, m_state);
    if (act.load_scene) m_loads.load(m_state);
    m_loads.drop(m_input.dropped, m_state, m_camera->desc());
    if (act.fill_default_sky) m_loads.environment("sky", m_state, m_camera->desc());
    poll_loading(now);
    handle_bookmarks(act, m_state, m_camera->desc(), m_scene.scene().source, m_log);
    m_compare_display.apply(act.compare, m_image.displayed(), m_image.shown(), m_denoising, m_camera->desc(), m_full_w,
                            m_full_h);
    return nav;
}

// Step 4: the image region is region_w x fb_h framebuffer pixels now; its first size posts the first render.
void Viewer::restart_on_change(const PanelActions& act, bool camera_moved, int region_w, int fb_h, double now) {
    const bool first = m_full_w == 0, resized = !first && (region_w != m_full_w || fb_h != m_full_h);
    m_full_w = region_w;
    m_full_h = fb_h;
    if (first) post(m_schedule.coarse("initial", now), false, false, now);
    m_scene.edited(act, m_state);
    if (glfwWindowShouldClose(m_window.get())) return;  // closing: nothing new to render
    const uint64_t posted_before = m_schedule.posted_generation();
    const double since = m_input.first_event >= 0.0 ? std::min(now, m_input.first_event) : now;
    ui::restart_on_change(*m_renderer, m_schedule, m_state, m_camera->desc(), m_full_w, m_full_h,
                          {act, camera_moved, resized, since, now}, m_image.shown(), m_pacing.is_minimised(), m_log);
    if (m_schedule.posted_generation() != posted_before) show_first_pass(now);
}

void Viewer::post(const RefinementSchedule::Restart& restart, bool with_materials, bool with_environment, double now) {
    const RenderRequest req = make_request(m_state, m_camera->desc(), m_full_w, m_full_h, m_schedule.level(),
                                           with_materials, with_environment);
    post_restart(*m_renderer, m_schedule, restart, req, m_log, now);
}

int run_viewer(const ViewerOptions& options) {
    Viewer viewer(options);
    return viewer.run();
}

}  // namespace pv::ui
