// core/render/light_groups.cpp: the scene's light groups (see light_groups.h).
#include "core/render/light_groups.h"

#include <algorithm>

namespace pv {

int LightGroups::find(const std::string& name) const {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : int(it - names.begin());
}

LightGroups make_light_groups(const Scene& scene, const std::vector<Material>& materials, const Environment& env) {
    // The groups in order of first appearance; past kMaxLightGroups - 1 distinct names, "other" takes the rest.
    std::vector<std::string> wanted;
    const auto want = [&](const std::string& name) {
        const auto it = std::find(wanted.begin(), wanted.end(), name);
        if (it != wanted.end()) return size_t(it - wanted.begin());
        wanted.push_back(name);
        return wanted.size() - 1;
    };
    std::vector<size_t> mat(materials.size(), 0), punctual(scene.punctual_lights.size(), 0);
    for (size_t i = 0; i < materials.size(); ++i)
        if (materials[i].has_emission())
            mat[i] = want(materials[i].light_group.empty() ? materials[i].name : materials[i].light_group);
    for (size_t i = 0; i < scene.punctual_lights.size(); ++i) {
        const std::string& n = scene.punctual_lights[i].name;
        punctual[i] = want(n.empty() ? "light" + std::to_string(i) : n);
    }
    const bool sky = !env.is_black() && env.sun_probability() < 1.f;
    const bool sun = !env.is_black() && env.sun_probability() > 0.f;
    size_t sky_i = 0, sun_i = 0;
    if (sky) sky_i = want("sky");
    if (sun) sun_i = want("sun");
    LightGroups g;
    const size_t cap = kMaxLightGroups;
    const size_t other = cap - 1;
    const auto id = [&](size_t w) { return uint8_t(wanted.size() > cap && w >= other ? other : w); };
    for (size_t i = 0; i < wanted.size() && i < cap; ++i)
        g.names.push_back(i == other && wanted.size() > cap ? "other" : wanted[i]);
    if (g.names.empty()) g.names.push_back("other");
    g.material.resize(materials.size());
    for (size_t i = 0; i < materials.size(); ++i) g.material[i] = id(mat[i]);
    g.punctual.resize(punctual.size());
    for (size_t i = 0; i < punctual.size(); ++i) g.punctual[i] = id(punctual[i]);
    g.sky = id(sky_i);
    g.sun = id(sun_i);
    return g;
}

}  // namespace pv
