// ui/scene_loads.cpp: see scene_loads.h.
#include "scene_loads.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <utility>

#include "core/load/scene_file.h"

namespace pv::ui {

LoadedScene SceneLoads::first(std::function<Scene()> load, const std::function<void(double)>& loading_frame) {
    const auto start = std::chrono::steady_clock::now();
    m_loader.start(std::move(load), m_threads);
    while (!m_loader.ready())
        loading_frame(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return m_loader.take();
}

void SceneLoads::load(ViewState& state) {
    if (m_loader.start([path = state.scene_path] { return pv::load_scene(path); }, m_threads))
        m_scene.load_started(state);
}

void SceneLoads::drop(std::vector<std::string>& dropped, ViewState& state, const CameraDesc& camera) {
    if (dropped.empty()) return;
    const DropRequest d = dispatch_drop(dropped);
    dropped.clear();
    state.drop_status = d.message;
    state.drop_ok = d.kind != DropKind::Unknown;
    if (d.kind != DropKind::Unknown && m_loader.busy()) {
        state.drop_status = d.path + ": not loaded, another load is running; drop it again when that ends";
        state.drop_ok = false;
    } else if (d.kind == DropKind::Scene) {
        state.scene_path = d.path;
        if (m_loader.start([path = d.path] { return pv::load_scene(path); }, m_threads)) {
            m_scene.load_started(state);
            m_drop_loading = d;
        }
    } else if (d.kind == DropKind::EnvironmentMap) {
        start_environment(d, state, camera);
    }
    m_log.line("drop %s", state.drop_status.c_str());
    if (!state.drop_ok) std::fprintf(stderr, "%s\n", state.drop_status.c_str());
}

void SceneLoads::environment(const std::string& spec, ViewState& state, const CameraDesc& camera) {
    if (m_loader.busy()) {
        state.drop_status = "environment " + spec + ": not added, a load is running; try again when it ends";
        state.drop_ok = false;
        return;
    }
    state.drop_status = "adding environment " + spec;
    state.drop_ok = true;
    start_environment(DropRequest{DropKind::EnvironmentMap, spec, state.drop_status}, state, camera);
    m_log.line("environment %s", spec.c_str());
}

void SceneLoads::start_environment(const DropRequest& request, ViewState& state, const CameraDesc& camera) {
    // The current scene with the new map, rebuilt off the UI thread like a loaded scene; the view stays.
    auto load = [scene = m_scene.shared(), path = request.path, camera, materials = state.materials,
                 environment = state.environment] {
        return with_environment_map(*scene, path, camera, materials, environment);
    };
    if (m_loader.start(load, m_threads)) {
        state.scene_loading = true;
        m_drop_loading = request;
    }
}

std::optional<LoadedScene> SceneLoads::take_finished(ViewState& state) {
    if (!m_loader.ready()) return std::nullopt;
    m_drop_taken = std::exchange(m_drop_loading, std::nullopt);
    try {
        return m_loader.take();
    } catch (const std::exception& e) {
        m_scene.load_failed(state, e.what());
        if (m_drop_taken) {
            state.drop_status = e.what();
            state.drop_ok = false;
            std::fprintf(stderr, "%s\n", e.what());
        }
        m_drop_taken.reset();
        return std::nullopt;
    }
}

void SceneLoads::adopted(ViewState& state) {
    m_scene.load_succeeded(state);
    if (const std::optional<DropRequest> dropped = std::exchange(m_drop_taken, std::nullopt)) {
        state.drop_status =
            (dropped->kind == DropKind::Scene ? "loaded scene " : "loaded environment map ") + dropped->path;
        state.drop_ok = true;
        m_log.line("drop %s", state.drop_status.c_str());
    }
}

}  // namespace pv::ui
