// core/scene_file.h: loading a scene from a JSON scene file or an OBJ alone.
// JSON (all keys but "obj" optional):
//   { "obj": "cornell-box.obj",                 // relative to the JSON file
//     "camera": { "eye": [x,y,z], "target": [x,y,z], "up": [x,y,z], "fov": 39.3,   // vertical, degrees
//                 "aperture": 0.0, "focus_distance": 0.0 },                         // lens radius; 0 = at target
//     "background": [r,g,b],                      // constant radiance of escaping rays (default black)
//     "environment": { "map": "sky.exr", "rotation": 0, "strength": 1 },  // equirectangular .exr/.hdr/.png
//     "sun": { "direction": [x,y,z], "irradiance": [r,g,b], "angular_radius": 0.27 },  // toward the sun; degrees
//     "two_sided_emitters": false,
//     "materials": { "name": { "type": "diffuse|glossy|mirror|glass", "base_color": [r,g,b],
//                              "specular": [r,g,b], "roughness": a, "ior": n, "emission": [r,g,b] } } }
// An OBJ alone is framed automatically from its bounds. A scene with no emitter and neither "background" nor
// "environment" is lit by the default sky (a warning says so). Errors are pv::Error naming the file.
#pragma once

#include "core/scene.h"

#include <string>

namespace pv {

// Loads `path` (.json or .obj). Throws pv::Error with "<file>: what is wrong".
Scene load_scene(const std::string& path);

// Sets the scene's environment from a user string: "r,g,b" or one number (constant radiance), or the path of an
// equirectangular map (.exr, .hdr, .png, .jpg). "sky" is the default sky. Throws pv::Error on a bad value or file.
void set_environment(Scene& scene, const std::string& spec);

}  // namespace pv
