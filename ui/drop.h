// ui/drop.h: files dropped on the window. A scene (.obj, .json, .gltf, .glb) loads as the Scene section's "Load"
// does; an image (.exr, .hdr, .png, .jpg) becomes the environment map of the current scene, which is rebuilt off the
// UI thread with the camera, materials and light as edited. Anything else gets one line naming the file. The
// dispatch by extension and the scene with a new map are window-free (tests/gui/test_ui_compare.cpp).
#pragma once

#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace pv::ui {

enum class DropKind { Scene, EnvironmentMap, Unknown };

// By the extension, in any letter case.
DropKind drop_kind(const std::string& path);

struct DropRequest {
    DropKind kind = DropKind::Unknown;
    std::string path;     // the file to load (the first scene or image dropped); empty when none
    std::string message;  // one line for the panel: what happens, or why nothing does
};

// Of the files dropped together, the first scene or image is loaded; the message names it (and how many others
// were ignored), or, when none is known, the first file and the extensions expected.
DropRequest dispatch_drop(const std::vector<std::string>& paths);

// `scene` lit by the equirectangular map at `map_path` (core/load/scene_file.h set_environment_map), seen from
// `camera`, with the materials and environment settings as edited in the viewer. Throws pv::Error naming the file.
Scene with_environment_map(const Scene& scene, const std::string& map_path, const CameraDesc& camera,
                           const std::vector<Material>& materials, const EnvironmentSettings& environment);

}  // namespace pv::ui
