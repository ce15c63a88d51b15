// core/traceable_scene.cpp: building and editing the scene prepared for tracing (see traceable_scene.h).
#include "core/traceable_scene.h"

namespace pv {

TraceableScene::TraceableScene(std::shared_ptr<const Scene> scene, const std::function<void(double)>& build_progress)
    : m_scene(std::move(scene)), m_materials(m_scene->materials) {
    m_accel = std::make_unique<Accel>(*m_scene, m_materials, build_progress);
    m_lights = LightSet(*m_scene, m_materials);
    m_environment_settings = m_scene->environment;
    m_environment = Environment(*m_scene, m_environment_settings);
    update_selection();
}

TraceableScene::~TraceableScene() = default;

void TraceableScene::set_materials(const std::vector<Material>& materials) {
    if (materials.size() != m_scene->materials.size()) return;
    m_materials = materials;
    m_lights = LightSet(*m_scene, m_materials);
    m_accel->set_materials(m_materials);  // alpha cut-outs as edited
    update_selection();
}

void TraceableScene::set_environment(const EnvironmentSettings& settings) {
    m_environment_settings = settings;
    m_environment = Environment(*m_scene, settings);
    update_selection();
}

void TraceableScene::update_selection() {
    // Half the light samples to the environment when both it and emissive triangles shine.
    if (m_environment.is_black())
        m_p_env = 0.f;
    else
        m_p_env = m_lights.empty() ? 1.f : 0.5f;
}

std::optional<PickResult> TraceableScene::pick(const Camera& camera, vec2 film_px) const {
    const Ray ray = camera.generate(film_px, vec2(0.5f));
    Hit hit;
    if (!intersect(ray, hit)) return std::nullopt;
    PickResult r;
    r.triangle = hit.prim;
    r.material = m_scene->material_ids[hit.prim];
    r.distance = hit.t;
    r.position = ray.o + hit.t * ray.d;
    return r;
}

}  // namespace pv
