// core/load/scene_file.h: loading a scene from a JSON scene file or an OBJ alone.
// JSON (all keys but "obj" optional):
//   { "obj": "cornell-box.obj",                 // relative to the JSON file; or a glTF file (.gltf, .glb)
//     "camera": { "eye": [x,y,z], "target": [x,y,z], "up": [x,y,z], "fov": 39.3,   // vertical, degrees
//                 "aperture": 0.0, "focus_distance": 0.0 },                         // lens radius; 0 = at target
//     "background": [r,g,b],                      // constant radiance of escaping rays (default black)
//     "environment": { "map": "sky.exr", "rotation": 0, "strength": 1 },  // equirectangular .exr/.hdr/.png,
//                                                                         // or "sky": the default sky
//     "sun": { "direction": [x,y,z], "irradiance": [r,g,b], "angular_radius": 0.27 },  // toward the sun; degrees
//     "portals": [ { "corner": [x,y,z], "edge1": [x,y,z], "edge2": [x,y,z] } ],  // parallelograms the sky shines
//                                                 // through (windows): light sampling aims at them (docs/portals.md);
//                                                 // edges within 1e9, non-zero area
//     "bookmarks": [ { "name": "door", "eye": [..], "target": [..], "up": [..], "fov": 40, ... } ],
//     "two_sided_emitters": false,
//     "materials": { "name": { "type": "diffuse|glossy|mirror|glass|metallic-roughness", "base_color": [r,g,b],
//                              "specular": [r,g,b], "roughness": a, "ior": n, "emission": [r,g,b],
//                              // metallic-roughness (glTF; "specular" is its specular colour, "roughness" the
//                              // perceptual roughness, alpha = roughness^2):
//                              "metallic": m, "transmission": t, "specular_factor": s, "thin_walled": true,
//                              "attenuation_color": [r,g,b], "attenuation_distance": d } } }
//   (through core/scene/material_params.h: a glossy material keeps diffuse + specular <= 1 per channel; a mirror
//   reflects its "specular" colour when given, else its base colour)
// An OBJ alone is framed automatically from its bounds; a glTF file starts at its first perspective camera (framed
// like an OBJ without one), its cameras listed as bookmarks before those of the JSON. A scene with no emitter and
// neither "background" nor "environment" is lit by the default sky (a warning says so). Errors are pv::Error naming the
// file.
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
