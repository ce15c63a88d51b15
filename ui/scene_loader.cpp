// ui/scene_loader.cpp: background scene loads (see scene_loader.h).
#include "scene_loader.h"

#include <chrono>

namespace pv::ui {

bool SceneLoader::start(std::function<Scene()> load, int threads) {
    if (m_job.valid()) return false;
    m_job = std::async(std::launch::async, [load = std::move(load), threads, wake = m_wake] {
        struct Wake {  // wakes the UI loop when the load ends, also by an exception
            const std::function<void()>& f;
            ~Wake() {
                if (f) f();
            }
        } on_exit{wake};
        LoadedScene loaded;
        loaded.scene = std::make_shared<const Scene>(load());
        loaded.renderer = std::make_unique<ProgressiveRenderer>(loaded.scene, threads);  // builds the BVH
        return loaded;
    });
    return true;
}

bool SceneLoader::ready() const {
    return m_job.valid() && m_job.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

}  // namespace pv::ui
