// ui/panel.h: the Dear ImGui side panel. It edits the viewer's state in place and reports what changed; the
// viewer decides what restarts (estimator, camera and material edits) and what only re-displays (exposure,
// tone map, views). Drawn between ImGui::NewFrame() and ImGui::Render().
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "camera_controller.h"
#include "compare.h"
#include "convergence.h"
#include "core/frame/renderer.h"
#include "core/scene/environment.h"
#include "display.h"
#include "display_transform.h"
#include "view_log.h"

namespace pv::ui {

// The state the panel edits.
struct ViewState {
    RenderSettings settings;
    std::vector<Material> materials;
    DisplayParams display;
    OcioChoice ocio;             // the OpenColorIO config offered in the Display section (ui/display_transform.h)
    int target_spp = 0;          // 0: none
    AdaptiveSettings adaptive;   // "stop at noise threshold" (0: off); a change restarts the accumulation
    float target_seconds = 0.f;  // 0: none
    bool paused = false;
    int selected_material = -1;
    bool pick_focus = false;  // the next click in the image sets the focus plane
    std::string snapshot_dir;
    std::string snapshot_status;
    bool snapshot_ok = true;
    std::string scene_path;  // the scene to load (Scene section)
    std::string scene_status;
    bool scene_ok = true;
    bool scene_loading = false;  // a load runs in the background
    std::string drop_status;     // the last file dropped on the window: loading, loaded, or what failed
    bool drop_ok = true;
    EnvironmentSettings environment;  // sky, map rotation/strength, sun (Light section)
    HomogeneousMedium fog;            // the global medium (Light section); edits post with the environment
    bool has_environment_map = false;
    std::vector<Scene::Bookmark> bookmarks;  // saved with the scene file (Camera section)
    std::string bookmark_status;
    bool bookmark_ok = true;
    // The render region in image pixels (Ctrl+left drag; X or "Clear region" clears it): every sample lands inside
    // it. Nothing: the whole image. Not applied while adaptive sampling is on.
    std::optional<PixelRect> region;
};

// Read-only facts the panel shows.
struct PanelFacts {
    const Snapshot* snapshot = nullptr;  // the one on screen
    const ConvergenceHistory* history = nullptr;
    std::string scene_name;
    size_t triangles = 0;
    std::vector<std::string> warnings;
    int full_width = 0, full_height = 0;  // the image region, in pixels
    int level = 1;                        // render resolution divisor (4, 2 or 1)
    double frame_ms = 0.0;                // the UI's last frame
    const Compare* compare = nullptr;
    bool compare_camera_moved = false;  // B was held from another camera
    bool dark_view = false;             // the view reads as dark and no sky or sun lights it (dark_view.h)
    double dark_mean = 0.0;             // its mean displayed luminance
};

// What the user asked for in this frame.
struct PanelActions {
    bool settings_changed = false;
    bool materials_changed = false;
    bool camera_changed = false;   // fov, aperture, focus distance
    bool control_changed = false;  // pause or targets
    bool restart = false;
    bool save = false;
    bool save_png = false;        // the image on screen through the view transform (Ctrl+Shift+S)
    bool save_resumable = false;  // a partial render that `pathview render --resume` continues
    bool frame_all = false;
    bool reset_camera = false;
    bool load_scene = false;
    bool environment_changed = false;
    bool fill_default_sky = false;  // the dark-view hint's "default sky": the scene rebuilt with it (scene_loads.h)
    int goto_bookmark = -1;         // index into ViewState::bookmarks
    std::string save_bookmark;      // non-empty: save the current camera under this name
    bool region_changed = false;    // ViewState::region set or cleared
    CompareActions compare;         // hold B, compare views, divider, load an EXR as B
};

class Panel {
public:
    explicit Panel(ViewLog& log) : m_log(log) {}
    // Draws the panel at the right edge of the window, `width` window pixels wide.
    PanelActions draw(ViewState& state, CameraController& camera, const PanelFacts& facts, float width);

private:
    void progress(ViewState& state, const PanelFacts& facts, PanelActions& act);
    void convergence(const PanelFacts& facts);
    void estimator(ViewState& state, const PanelFacts& facts, PanelActions& act);
    void display(ViewState& state, const PanelFacts& facts);
    void view_transform(ViewState& state);  // ui/panel_view_transform.cpp
    void camera(ViewState& state, CameraController& camera, PanelActions& act);
    void materials(ViewState& state, PanelActions& act);
    void snapshots(ViewState& state, PanelActions& act);
    void scene(ViewState& state, PanelActions& act);
    void lighting(ViewState& state, PanelActions& act);
    void dark_view_hint(ViewState& state, const PanelFacts& facts, PanelActions& act);
    void bookmarks(ViewState& state, PanelActions& act);
    void compare(const PanelFacts& facts, PanelActions& act);
    // Logs the centre of the last item, once per position change (the GUI test clicks it).
    void log_widget(const char* name);

    ViewLog& m_log;
    std::map<std::string, std::pair<int, int>> m_logged;
    char m_scene_path[1024] = {};    // the Scene section's text field
    std::string m_field_scene_path;  // state.scene_path when the field was last set from it
    char m_bookmark_name[128] = "view 1";
    char m_compare_path[1024] = {};  // the Compare section's EXR path
};

// What the image shown is: "DENOISED at 9/9 spp", "RAW", "RAW (denoising...)" or "false colour (raw)".
std::string shown_image(const ViewState& state, const Snapshot* snapshot);

// Labels the compare views on the image (A and B either side of the split's divider, "B", the difference's scale)
// with ImGui's background draw list; `image_w` x `image_h`: the image region in window pixels.
void draw_compare_overlay(const Compare& compare, bool camera_moved, float image_w, float image_h);

}  // namespace pv::ui
