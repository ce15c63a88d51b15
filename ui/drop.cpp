// ui/drop.cpp: files dropped on the window (see drop.h).
#include "drop.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "core/load/scene_file.h"

namespace pv::ui {

DropKind drop_kind(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".obj" || ext == ".json" || ext == ".gltf" || ext == ".glb") return DropKind::Scene;
    if (ext == ".exr" || ext == ".hdr" || ext == ".png" || ext == ".jpg" || ext == ".jpeg")
        return DropKind::EnvironmentMap;
    return DropKind::Unknown;
}

DropRequest dispatch_drop(const std::vector<std::string>& paths) {
    DropRequest r;
    if (paths.empty()) return r;
    const auto known = std::find_if(paths.begin(), paths.end(),
                                    [](const std::string& p) { return drop_kind(p) != DropKind::Unknown; });
    if (known == paths.end()) {
        r.message = paths.front() +
                    ": unknown file type; drop a scene (.obj, .json, .gltf, .glb) or an environment map (.exr, .hdr, "
                    ".png)";
        return r;
    }
    r.kind = drop_kind(*known);
    r.path = *known;
    r.message = (r.kind == DropKind::Scene ? "loading scene " : "loading environment map ") + r.path + " ...";
    if (paths.size() > 1)
        r.message +=
            " (" + std::to_string(paths.size() - 1) + " other file" + (paths.size() > 2 ? "s" : "") + " ignored)";
    return r;
}

Scene with_environment_map(const Scene& scene, const std::string& map_path, const CameraDesc& camera,
                           const std::vector<Material>& materials, const EnvironmentSettings& environment) {
    Scene s = scene;
    s.environment_map = kNoIndex;  // as `--environment MAP`: the new map replaces the old one
    set_environment_map(s, map_path);
    if (s.default_sky_warning && *s.default_sky_warning < s.warnings.size())  // the default sky no longer lights it
        s.warnings.erase(s.warnings.begin() + std::ptrdiff_t(*s.default_sky_warning));
    s.default_sky_warning.reset();
    s.camera = camera;
    if (materials.size() == s.materials.size()) s.materials = materials;
    s.environment = environment;
    return s;
}

}  // namespace pv::ui
