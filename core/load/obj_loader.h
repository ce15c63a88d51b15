// core/load/obj_loader.h: Wavefront OBJ/MTL import through tinyobjloader, with the validation tinyobjloader lacks.
#pragma once

#include <string>

#include "core/scene/scene.h"

// Validation and defaults:
// Errors (pv::Error, "<file>:<line>: what; expected"): missing/unreadable file, out-of-range or wrapped face
// indices, a zero face index, unparseable OBJ. Dropped and counted (one warning each): triangles with a
// non-finite or absurd (|x| > 1e18) vertex, zero-area triangles, faces that are not triangles after
// triangulation. Defaults: a missing or unknown material gets the default material (grey Lambertian 0.8),
// zero/NaN normals fall back to the geometric normal.
//
// MTL -> material ("model only what a scene needs"; see docs in README):
//   illum 4, 6, 7, or d < 1 with Ni > 1 -> Dielectric (eta = Ni; 1.5 when Ni <= 1)
//   (d < 1 without Ni is rendered opaque, with a warning; Tr is ignored when d is present, as tinyobjloader does)
//   illum 3, 5                -> Mirror (reflectance Ks, or 1 when Ks = 0)
//   Ks > 0 (illum != 0, 1)    -> Glossy: Kd diffuse + GGX lobe with F = Ks, alpha = sqrt(2 / (Ns + 2))
//   otherwise                 -> Lambertian (Kd)
//   Ke > 0                    -> emission on the front face (winding order), plus the reflective part above.
//   Ka is ignored: some exporters put emission there (Embree's cornell_box.obj), but MTL's Ka is ambient
//   reflectance, not emission. Tf (transmission filter) and bump maps are ignored.
//   map_Kd -> base colour texture; it REPLACES Kd (exporters such as 3ds Max and Blender write Kd as a preview
//   colour next to the map). map_d, or map_Kd's alpha channel -> stochastic alpha cut-out (shadow rays too).
//   Texture names are matched case-insensitively when the exact name is missing; a missing texture gives one
//   warning and the flat colour.
// When Kd + Ks exceeds 1 in a channel both are scaled down to sum to 1 (energy conservation), with a warning.

namespace pv {

struct ObjOptions {
    bool two_sided_emission = false;
};

// Loads an OBJ file (and its MTL files, relative to the OBJ's folder).
Scene load_obj(const std::string& path, const ObjOptions& options = {});
// Loads OBJ text (no MTL); `name` is used in messages. For tests and the fuzzer.
Scene load_obj_from_string(const std::string& text, const std::string& name, const ObjOptions& options = {});
// Converts MTL-style parameters to a material as described above; warnings are appended.
Material material_from_mtl(const std::string& name, vec3 kd, vec3 ks, vec3 ke, float ns, float ni, float d, int illum,
                           std::vector<std::string>& warnings);

}  // namespace pv
