// core/load/scene_file.h: loading a scene from a JSON scene file, an OBJ alone or a glTF file, and saving camera
// bookmarks into a scene file. The JSON keys, their defaults and how a scene without a camera or light is framed and
// lit: docs/scene-format.md.
#pragma once

#include <string>

#include "core/scene/scene.h"

namespace pv {

// Loads `path` (.json, .obj, .gltf or .glb), its textures' texels packed into one region once it is complete
// (pack_texels). Throws pv::Error with "<file>: what is wrong".
Scene load_scene(const std::string& path);
// Loads a JSON scene file's text; `path` names it in messages and relative paths start from its folder (the
// fuzzer's entry point). Errors name the file and the JSON pointer of the key: "s.json: /camera/fov: expected ...".
Scene load_scene_json_text(const std::string& text, const std::string& path);

// Saves `camera` as bookmark `name` (replacing one of that name) in the scene file `path`: a JSON scene file is
// rewritten with its other keys kept; for an OBJ, a scene file "<obj>.json" next to it is created or updated.
// Returns the scene file written. Written to a temporary file and renamed. Throws pv::Error on failure.
std::string save_bookmark(const std::string& path, const std::string& name, const CameraDesc& camera);
// The bookmark called `name`; throws pv::Error listing the names there are when none matches.
const CameraDesc& find_bookmark(const Scene& scene, const std::string& name);

// Lights the scene with the equirectangular map at `path` (.exr, .hdr, .png, .jpg), or the default sky for "sky".
// Throws pv::Error on a bad file. (A constant colour is Scene::background with no map.) The scene's texels are packed
// again (pack_texels), the map with them.
void set_environment_map(Scene& scene, const std::string& path);

}  // namespace pv
