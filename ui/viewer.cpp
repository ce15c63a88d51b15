// ui/viewer.cpp: the main loop, after Dear ImGui's example: 1 wait for input or a published pass (capped at the
// display rate; sleep while minimised), 2 new ImGui frame and the panel, 3 camera input where ImGui does not
// want it, 4 restart on a change, 5 snapshot -> texture -> display pass, 6 ImGui on top, swap.
// Each step calls into a room that owns one concern; all but window.h and display.h need no window:
// window.h (GLFW, GL context, ImGui set-up, loading screen), navigation.h (gestures -> camera), refinement.h
// (coarse -> ... -> full resolution, the coarse level from measured pass times, deferral, latency), restarts.h (change
// -> request -> renderer), shown_image.h (the accumulation on screen and its convergence history), scene_loader.h
// (loads off the UI thread), active_scene.h (the scene's state and warnings), bookmarks.h, snapshots.h (EXR snapshots),
// frame_stats.h (telemetry), panel.h (the ImGui panel), display.h (the GL display pass).
#include "viewer.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <utility>

#include "active_scene.h"
#include "bookmarks.h"
#include "camera_controller.h"
#include "compare.h"
#include "core/load/scene_file.h"
#include "display.h"
#include "drop.h"
#include "frame_stats.h"
#include "navigation.h"
#include "panel.h"
#include "refinement.h"
#include "restarts.h"
#include "scene_loader.h"
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
    ~Viewer();
    int run();

private:
    bool wait_for_work();
    NavigationFrame navigation_frame(double dt) const;
    void restart_on_change(const PanelActions& act, bool camera_moved, bool resized, double now);
    void post(const RefinementSchedule::Restart& restart, bool with_materials, bool with_environment, double now);
    // Renders `loaded.scene` from now on with its renderer (the old one is joined).
    void use_scene(LoadedScene loaded);
    // Loads the scene of the command line in the background while the window shows a loading screen.
    LoadedScene load_first_scene();
    // Adopts a finished background load (the panel's "Load"); on failure the current scene stays.
    void poll_loading(double now);
    // The compare views (compare.h): applies the frame's actions, keeps B's texture and the difference current.
    void update_compare(const CompareActions& act);
    // Files dropped on the window (drop.h): a scene loads as the Scene section's "Load"; an image becomes the map.
    void handle_drops();
    void upload_difference();
    // The image on screen as PNG through the view transform; the display pass's bytes go along to be compared.
    void save_png();
    void log_error_vs_b();
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
    FrameStats m_frame_stats;
    ViewState m_state;

    int m_full_w = 0, m_full_h = 0;  // image region, framebuffer pixels
    float m_fb_scale = 1.f;          // framebuffer pixels per window pixel
    double m_last_frame = -1.0;
    int m_settle_frames = 0;
    bool m_minimised = false;
    bool m_denoising = false;                   // the driver's denoising, as last set from m_state.display.denoise
    std::optional<DropRequest> m_drop_loading;  // the drop that started the background load
};

Viewer::Viewer(const ViewerOptions& o)
    : m_opt(o),
      m_log(o.log_file),
      m_window(o.width + int(kPanelWidth), o.height, "pathview - loading", &m_input),
      m_display(std::make_unique<DisplayPass>()),
      m_snapshots(
          o.snapshot_dir, [] { glfwPostEmptyEvent(); }, m_log) {
    LoadedScene first = load_first_scene();
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
    if (o.compare_image) {
        m_compare.set_b(*o.compare_image, o.compare_path);
        m_display->upload_b(m_compare.b());
        m_log.line("compare %s", m_compare.status().c_str());
    }
    m_log.line("start scene=%s triangles=%zu threads=%d gl=\"%s\" refresh_hz=%.0f", m_scene.scene().source.c_str(),
               m_scene.scene().triangle_count(), m_renderer->threads(),
               reinterpret_cast<const char*>(glGetString(GL_RENDERER)), m_window.refresh_hz());
}

Viewer::~Viewer() {
    m_loader.wait();  // a background load ends first (it may still post an event to the window)
}

LoadedScene Viewer::load_first_scene() {
    // The window says what it is doing meanwhile and stays responsive.
    const double start = glfwGetTime();
    m_loader.start(m_opt.load_scene, m_opt.threads);
    while (!m_loader.ready()) m_window.loading_frame(glfwGetTime() - start);
    m_input = InputQueue{};  // input given to the loading screen does not move the camera afterwards,
    m_input.any = true;      // but the first frame is drawn at once
    return m_loader.take();  // a load error propagates: one line naming the file, and a non-zero exit
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
    if (!m_loader.ready()) return;
    const std::optional<DropRequest> dropped = std::exchange(m_drop_loading, std::nullopt);
    try {
        use_scene(m_loader.take());
    } catch (const std::exception& e) {
        m_scene.load_failed(m_state, e.what());
        if (dropped) {
            m_state.drop_status = e.what();
            m_state.drop_ok = false;
            std::fprintf(stderr, "%s\n", e.what());
        }
        return;
    }
    m_scene.load_succeeded(m_state);
    if (dropped) {
        m_state.drop_status =
            (dropped->kind == DropKind::Scene ? "loaded scene " : "loaded environment map ") + dropped->path;
        m_state.drop_ok = true;
        m_log.line("drop %s", m_state.drop_status.c_str());
    }
    post(m_schedule.coarse("scene", now), false, false, now);
}

void Viewer::handle_drops() {
    if (m_input.dropped.empty()) return;
    const DropRequest d = dispatch_drop(m_input.dropped);
    m_input.dropped.clear();
    m_state.drop_status = d.message;
    m_state.drop_ok = d.kind != DropKind::Unknown;
    if (d.kind != DropKind::Unknown && m_loader.busy()) {
        m_state.drop_status = d.path + ": not loaded, another load is running; drop it again when that ends";
        m_state.drop_ok = false;
    } else if (d.kind == DropKind::Scene) {
        m_state.scene_path = d.path;
        if (m_loader.start([path = d.path] { return pv::load_scene(path); }, m_opt.threads)) {
            m_scene.load_started(m_state);
            m_drop_loading = d;
        }
    } else if (d.kind == DropKind::EnvironmentMap) {
        // The current scene with the new map, rebuilt off the UI thread like a loaded scene; the view stays.
        auto load = [scene = m_scene.shared(), path = d.path, camera = m_camera->desc(), materials = m_state.materials,
                     environment = m_state.environment] {
            return with_environment_map(*scene, path, camera, materials, environment);
        };
        if (m_loader.start(load, m_opt.threads)) {
            m_state.scene_loading = true;
            m_drop_loading = d;
        }
    }
    m_log.line("drop %s", m_state.drop_status.c_str());
    if (!m_state.drop_ok) std::fprintf(stderr, "%s\n", m_state.drop_status.c_str());
}

void Viewer::save_png() {
    // The screen holds exactly the shown image in the colour view without a comparison or a region's backdrop.
    const DisplayParams& d = m_state.display;
    const bool comparable = d.view == View::Colour && d.compare == CompareView::Off && !m_state.region;
    m_snapshots.save_png(m_image.shown(), d.denoise, d, comparable ? m_display->read_shaded(d) : std::vector<uint8_t>{},
                         m_state);
}

// Takes the renderer's newest pass, if there is one, onto the screen's textures and the comparison; true if it did.
bool Viewer::take_latest() {
    if (!m_image.update([this](Snapshot& s) { return m_renderer->latest(s); })) return false;
    m_display->upload(m_image.displayed(), m_state.display.denoise);
    m_frame_stats.pass_shown(m_state.display.denoise && !m_image.displayed().denoised.empty() &&
                             m_image.displayed().denoised_spp == m_image.displayed().spp);
    m_compare.update(m_image.shown());
    log_error_vs_b();
    upload_difference();
    // The next change restarts at the finest resolution whose first frame is predicted to be ready within
    // half a display refresh (the rest goes to the UI: its frame, llvmpipe sharing the cores).
    const Snapshot& s = m_image.shown();
    if (m_full_w > 0)
        m_schedule.measured_first_pass(s.first_ready_ms * 1e-3, s.width * s.height, double(m_full_w) * m_full_h,
                                       0.5 / m_window.refresh_hz());
    return true;
}

// A restart was posted in this frame: its first pass, sized to be ready within half a refresh
// (RefinementSchedule), is waited for until this refresh ends and drawn in this very frame, instead of the frame
// drawing the old image and the next one the new: input to frame loses one frame's drawing. Never longer than a
// refresh: a slower pass is shown by a later frame, as before.
void Viewer::show_first_pass(double frame_start) {
    const double left = frame_start + 1.0 / m_window.refresh_hz() - glfwGetTime();
    if (left <= 0.0) return;
    const auto timeout = std::chrono::milliseconds(std::max(1L, long(left * 1e3)));
    if (m_renderer->wait_for(m_schedule.posted_generation(), 1, timeout)) take_latest();
}

bool Viewer::wait_for_work() {
    // Minimised: pause rendering and sleep until the window comes back.
    GLFWwindow* window = m_window.get();
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    if (glfwGetWindowAttrib(window, GLFW_ICONIFIED) || fb_w == 0 || fb_h == 0) {
        if (!m_minimised) {
            m_minimised = true;
            apply_controls(*m_renderer, m_state, m_minimised);
            m_log.line("minimised: paused");
        }
        glfwWaitEvents();
        m_input.first_event = -1.0;
        return false;
    }
    if (m_minimised) {
        m_minimised = false;
        apply_controls(*m_renderer, m_state, m_minimised);
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
    // The first pass of a new accumulation is shown at once, though: it answers an input event. A press, scroll,
    // drop or drag is handled after half a refresh (at most two frames a refresh): waiting out the whole refresh put
    // up to 17 ms between a drag and the restart it posts.
    const double next = m_last_frame + 1.0 / m_window.refresh_hz();
    const double next_urgent = m_last_frame + 0.5 / m_window.refresh_hz();
    for (double now = glfwGetTime(); now < next; now = glfwGetTime()) {
        if (m_renderer->published_generation() > m_image.shown().generation) break;
        if (m_input.urgent && now >= next_urgent) break;
        glfwWaitEventsTimeout((m_input.urgent ? next_urgent : next) - now);
    }
    glfwPollEvents();

    bool work = continuous || m_input.any || m_schedule.deferral_expired(glfwGetTime());
    if (take_latest()) work = true;
    if (m_snapshots.save_partial(m_renderer->take_partial(), m_state)) work = true;
    if (std::string refusal = m_renderer->take_partial_refusal(); !refusal.empty()) {
        m_state.snapshot_status = std::move(refusal);
        m_state.snapshot_ok = false;
        work = true;
    }
    if (m_snapshots.poll(m_state)) work = true;
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
        const double dt = m_last_frame < 0.0 ? 0.0 : std::min(start - m_last_frame, 0.1);
        m_last_frame = start;
        m_settle_frames = m_input.any ? 2 : std::max(m_settle_frames - 1, 0);
        int fb_w, fb_h, win_w, win_h;
        glfwGetFramebufferSize(window, &fb_w, &fb_h);
        glfwGetWindowSize(window, &win_w, &win_h);
        m_fb_scale = win_w > 0 ? float(fb_w) / float(win_w) : 1.f;
        const int panel_fb = int(kPanelWidth * m_fb_scale);

        // 2. New ImGui frame; the panel edits m_state and the camera's lens in place.
        m_window.new_imgui_frame();
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
        PanelActions act = m_panel.draw(m_state, *m_camera, facts, kPanelWidth);
        draw_compare_overlay(m_compare, facts.compare_camera_moved, float(m_full_w) / m_fb_scale,
                             float(m_full_h) / m_fb_scale);
        if (m_state.display.denoise != m_denoising) {  // a display change: the accumulation is not restarted
            m_denoising = m_state.display.denoise;
            m_renderer->set_denoise(m_denoising);
            m_display->upload(m_image.displayed(), m_denoising);
            upload_difference();
            m_log.line("denoise %d", int(m_denoising));
        }

        // 3. Camera and shortcuts where ImGui does not want the mouse or keyboard; scene loads, bookmarks, saves.
        const NavigationResult nav = m_navigation.handle(m_input, navigation_frame(dt), *m_camera, m_state, act);
        if (nav.quit) glfwSetWindowShouldClose(window, GLFW_TRUE);
        if (act.save) m_snapshots.save(m_image.shown(), m_state);
        if (act.save_png) save_png();
        if (act.save_resumable) {
            m_renderer->request_partial();
            m_snapshots.resumable_requested(m_state);
        }
        if (act.load_scene &&
            m_loader.start([path = m_state.scene_path] { return pv::load_scene(path); }, m_opt.threads))
            m_scene.load_started(m_state);
        handle_drops();
        poll_loading(start);
        handle_bookmarks(act, m_state, m_camera->desc(), m_scene.scene().source, m_log);
        update_compare(act.compare);

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
        const uint64_t posted_before = m_schedule.posted_generation();
        restart_on_change(act, nav.camera_moved, resized, start);
        if (m_schedule.posted_generation() != posted_before) show_first_pass(start);

        // 5. The accumulation through the display pass, in the image region.
        glViewport(0, 0, fb_w, fb_h);
        glClearColor(0.08f, 0.08f, 0.08f, 1.f);
        glClear(GL_COLOR_BUFFER_BIT);
        m_state.display.compare = m_compare.view();
        m_state.display.divider = m_compare.divider();
        m_display->draw(0, 0, m_full_w, m_full_h, m_state.display);

        // 6. The panel on top; swap.
        m_window.render_imgui_and_swap();

        const double end = glfwGetTime();
        m_frame_stats.end_frame((end - start) * 1e3);
        log_frames_shown(m_log, m_schedule, m_image.shown(), end);
        m_input.any = false;
        m_input.urgent = false;
        m_input.first_event = -1.0;
    }
    m_log.line("exit frames=%d", m_frame_stats.total_frames());
    return 0;
}

void Viewer::update_compare(const CompareActions& act) {
    const std::string status = m_compare.status();
    const std::string source = m_compare.source();
    const CompareView view = m_compare.view();
    if (!m_compare.apply(act, m_image.displayed(), m_denoising, m_camera->desc(), m_full_w, m_full_h)) return;
    if (m_compare.source() != source || act.hold || !act.load.empty()) m_display->upload_b(m_compare.b());
    upload_difference();
    if (m_compare.status() != status || act.hold || !act.load.empty()) {
        m_log.line("compare %s", m_compare.status().c_str());
        if (!m_compare.ok()) std::fprintf(stderr, "%s\n", m_compare.status().c_str());
    }
    if (m_compare.view() != view) m_log.line("compare view=%s", compare_view_name(m_compare.view()));
    m_compare.update(m_image.shown());
}

void Viewer::upload_difference() {
    if (m_compare.view() != CompareView::Difference) return;
    const Snapshot& a = m_image.displayed();
    const bool denoised = m_denoising && a.denoised.size() == a.rgb.size();
    m_display->upload_difference(m_compare.difference((denoised ? a.denoised : a.rgb).data(), a.width, a.height),
                                 a.width, a.height);
}

// With a B (e.g. a converged reference, --compare), each newly shown pass logs its relMSE against B: of the image
// on screen (the denoised one when shown) and of the raw mean. tests/gui/measure_viewer.sh's settle time reads it.
void Viewer::log_error_vs_b() {
    const auto raw = m_compare.rel_mse();
    if (!raw) return;
    const Snapshot& s = m_image.shown();
    const bool denoised = m_denoising && m_compare.rel_mse_denoised() >= 0.0;
    m_log.line("error gen=%llu spp=%u denoised_spp=%u shown=%s rel_mse_shown=%.4e rel_mse_raw=%.4e",
               (unsigned long long)s.generation, s.spp, s.denoised_spp,
               denoised ? (s.denoised_nfor ? "nfor" : "atrous") : "raw", denoised ? m_compare.rel_mse_denoised() : *raw,
               *raw);
}

NavigationFrame Viewer::navigation_frame(double dt) const {
    NavigationFrame f;
    double cx, cy;
    glfwGetCursorPos(m_window.get(), &cx, &cy);
    f.cursor = vec2(float(cx), float(cy));
    f.image_size = vec2(float(m_full_w), float(m_full_h)) / m_fb_scale;
    f.render_size = vec2(float(m_full_w), float(m_full_h));
    glfwGetWindowSize(m_window.get(), nullptr, &f.window_height);
    f.imgui_wants_mouse = ImGui::GetIO().WantCaptureMouse;
    f.imgui_wants_keyboard = ImGui::GetIO().WantCaptureKeyboard;
    f.dt = dt;
    f.pick = [this](vec2 window_pos) {
        return m_renderer->pick(m_camera->desc(), m_full_w, m_full_h, window_pos * m_fb_scale);
    };
    return f;
}

void Viewer::restart_on_change(const PanelActions& act, bool camera_moved, bool resized, double now) {
    if (glfwWindowShouldClose(m_window.get())) return;  // closing: nothing new to render
    if (act.control_changed) {
        apply_controls(*m_renderer, m_state, m_minimised);
        m_log.line("control paused=%d target_spp=%d target_seconds=%g", int(m_state.paused), m_state.target_spp,
                   double(m_state.target_seconds));
    }
    m_scene.edited(act, m_state);
    const double since = m_input.first_event >= 0.0 ? std::min(now, m_input.first_event) : now;
    const std::string reason = restart_reason(act, camera_moved, resized);
    if (const auto restart = m_schedule.update(reason, now, since, m_image.shown().generation, m_image.shown().spp))
        post(*restart, act.materials_changed, act.environment_changed, now);
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
