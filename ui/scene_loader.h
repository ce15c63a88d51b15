// ui/scene_loader.h: loading a scene off the UI thread. The parse and the BVH build (the ProgressiveRenderer's
// constructor) run on a worker thread, so the window stays responsive and the current scene keeps rendering; when
// the load ends, also by an error, `wake` runs (the viewer posts an empty GLFW event with it). Window-free.
#pragma once

#include <functional>
#include <future>
#include <memory>

#include "core/frame/progressive.h"

namespace pv::ui {

struct LoadedScene {
    std::shared_ptr<const Scene> scene;
    std::unique_ptr<ProgressiveRenderer> renderer;
};

class SceneLoader {
public:
    explicit SceneLoader(std::function<void()> wake) : m_wake(std::move(wake)) {}
    ~SceneLoader() { wait(); }  // a load in flight may still call wake: it ends first
    SceneLoader(const SceneLoader&) = delete;
    SceneLoader& operator=(const SceneLoader&) = delete;

    // Starts loading with `load` (which throws pv::Error on a bad file) and building a renderer with `threads`
    // workers; false, and nothing started, while another load runs.
    bool start(std::function<Scene()> load, int threads);
    bool busy() const { return m_job.valid(); }
    // True once a started load has ended (take() then returns at once).
    bool ready() const;
    // The finished load; rethrows its error. Only after ready().
    LoadedScene take() { return m_job.get(); }
    void wait() const {
        if (m_job.valid()) m_job.wait();
    }

private:
    std::function<void()> m_wake;
    std::future<LoadedScene> m_job;
};

}  // namespace pv::ui
