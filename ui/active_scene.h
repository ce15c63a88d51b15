// ui/active_scene.h: the scene on screen and what the viewer derives from it: the ViewState fields a new scene
// resets (materials, selection, environment, bookmarks), the scene-level warnings (the loader's, plus "no
// emitters" when nothing emits), kept current while the panel edits materials and the environment, and the Scene
// section's load status. Window-free.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "panel.h"
#include "view_log.h"

namespace pv::ui {

// The loader's warnings, plus "no emitters ..." when no triangle of `scene` emits with `materials` and the
// environment gives no light.
std::vector<std::string> scene_warnings(const Scene& scene, const std::vector<Material>& materials,
                                        bool environment_lit);

class ActiveScene {
public:
    explicit ActiveScene(ViewLog& log) : m_log(log) {}

    // Shows `scene` from now on: resets the state's materials, selection, environment and bookmarks from it and
    // logs its warnings.
    void adopt(std::shared_ptr<const Scene> scene, ViewState& state);
    // After this frame's panel edits: the warnings follow material and environment changes.
    void edited(const PanelActions& act, const ViewState& state);

    // The Scene section's status: a background load of state.scene_path started, succeeded (after adopt()) or
    // failed with `error` (the current scene stays).
    void load_started(ViewState& state);
    void load_succeeded(ViewState& state);
    void load_failed(ViewState& state, const std::string& error);

    const Scene& scene() const { return *m_scene; }
    std::shared_ptr<const Scene> shared() const { return m_scene; }
    const std::vector<std::string>& warnings() const { return m_warnings; }
    bool environment_lit() const { return m_environment_lit; }
    // The file name of the scene's source ("scene.json").
    std::string file_name() const;

private:
    ViewLog& m_log;
    std::shared_ptr<const Scene> m_scene;
    std::vector<std::string> m_warnings;
    bool m_environment_lit = false;
};

}  // namespace pv::ui
