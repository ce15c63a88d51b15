// ui/scene_loads.h: the viewer's scene loads, from the panel's "Load", from files dropped on the window (a scene, or
// an environment map that rebuilds the current scene with it) and their outcome: a finished load to adopt, or an
// error reported in the Scene section (and, for a drop, on stderr) while the current scene stays. Loads run off the
// UI thread (scene_loader.h). Window-free.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "active_scene.h"
#include "drop.h"
#include "scene_loader.h"

namespace pv::ui {

class SceneLoads {
public:
    SceneLoads(SceneLoader& loader, ActiveScene& scene, ViewLog& log, int threads)
        : m_loader(loader), m_scene(scene), m_log(log), m_threads(threads) {}
    ~SceneLoads() { m_loader.wait(); }  // a load in flight ends first (it may still post an event to the window)
    SceneLoads(const SceneLoads&) = delete;
    SceneLoads& operator=(const SceneLoads&) = delete;

    // The first scene: `load` in the background while `loading_frame(seconds so far)` draws a loading screen (and
    // waits a little for events); a load error propagates: one line naming the file, and a non-zero exit.
    LoadedScene first(std::function<Scene()> load, const std::function<void(double)>& loading_frame);
    // The Scene section's "Load": state.scene_path in the background.
    void load(ViewState& state);
    // Files dropped on the window (cleared): the first scene loads as "Load" does; the first image becomes the
    // current scene's environment map, seen from `camera`. One load at a time: a drop during a load is refused.
    void drop(std::vector<std::string>& dropped, ViewState& state, const CameraDesc& camera);
    // The current scene rebuilt with the environment `spec` (as --environment: "sky", a colour or a map), seen from
    // `camera`, in the background as a dropped map is; refused (said in the Scene section) during another load.
    void environment(const std::string& spec, ViewState& state, const CameraDesc& camera);
    // A load that has ended: the scene to adopt, or nothing (none ended, or it failed: reported in `state`).
    std::optional<LoadedScene> take_finished(ViewState& state);
    // After the viewer adopted what take_finished() returned (ActiveScene::adopt): the Scene section (and a drop's
    // status) say so.
    void adopted(ViewState& state);

private:
    // Starts the rebuild of the current scene with environment `spec`; the outcome is reported as `request`'s.
    void start_environment(const DropRequest& request, ViewState& state, const CameraDesc& camera);

    SceneLoader& m_loader;
    ActiveScene& m_scene;
    ViewLog& m_log;
    int m_threads;
    std::optional<DropRequest> m_drop_loading;  // the drop that started the background load
    std::optional<DropRequest> m_drop_taken;    // the drop whose load take_finished() returned
};

}  // namespace pv::ui
