// ui/active_scene.cpp: the scene on screen (see active_scene.h).
#include "active_scene.h"

#include <filesystem>

#include "core/scene/environment.h"

namespace pv::ui {

std::vector<std::string> scene_warnings(const Scene& scene, const std::vector<Material>& materials,
                                        bool environment_lit) {
    std::vector<std::string> out = scene.warnings;
    bool lit = environment_lit;
    for (uint32_t id : scene.material_ids) lit = lit || (id < materials.size() && materials[id].has_emission());
    if (!lit) out.push_back("no emitters and a black environment: the image will be black");
    return out;
}

void ActiveScene::adopt(std::shared_ptr<const Scene> scene, ViewState& state) {
    m_scene = std::move(scene);
    state.materials = m_scene->materials;
    state.selected_material = -1;
    m_environment_lit = environment_emits(*m_scene, m_scene->environment);
    state.environment = m_scene->environment;
    state.fog = m_scene->fog;
    state.has_environment_map = m_scene->environment_map != kNoIndex;
    state.bookmarks = m_scene->bookmarks;
    state.bookmark_status.clear();
    m_warnings = scene_warnings(*m_scene, state.materials, m_environment_lit);
    for (const std::string& w : m_warnings) m_log.line("warning %s", w.c_str());
}

void ActiveScene::edited(const PanelActions& act, const ViewState& state) {
    if (act.environment_changed) m_environment_lit = environment_emits(*m_scene, state.environment);
    if (act.materials_changed || act.environment_changed)
        m_warnings = scene_warnings(*m_scene, state.materials, m_environment_lit);
}

void ActiveScene::load_started(ViewState& state) {
    state.scene_loading = true;
    state.scene_status = "loading " + state.scene_path + " ...";
    state.scene_ok = true;
    m_log.line("scene-loading path=%s", state.scene_path.c_str());
}

void ActiveScene::load_succeeded(ViewState& state) {
    state.scene_loading = false;
    state.scene_status = "loaded " + state.scene_path;
    state.scene_ok = true;
    m_log.line("scene path=%s triangles=%zu", state.scene_path.c_str(), m_scene->triangle_count());
}

void ActiveScene::load_failed(ViewState& state, const std::string& error) {
    state.scene_loading = false;
    state.scene_status = error;
    state.scene_ok = false;
    m_log.line("scene-error %s", error.c_str());
}

std::string ActiveScene::file_name() const { return std::filesystem::path(m_scene->source).filename().string(); }

}  // namespace pv::ui
