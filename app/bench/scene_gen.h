// app/bench/scene_gen.h: scenes generated at run time, by keyword, for benchmarks (a large mesh is not shipped).
#pragma once

#include <optional>
#include <string>

#include "core/scene/scene.h"

namespace pv {

// The keywords:
//   "large-mesh": the built-in Cornell box with a displaced sphere of 1,046,528 triangles (1024 x 512 grid) on a
//                 white diffuse material, standing in for the box's contents.
//   "many-lights": assets/many-lights (scripts/make_many_lights.py): a room of 320 small lamps of radiances over
//                 five decades, for the light tree (--light-sampler tree).
//   "compressed-instanced": assets/compressed-instanced/scene.glb (scripts/make_compressed_showcase.sh): a
//                 meshopt-compressed, quantized mesh placed by 400 nodes (384,002 triangles drawn); its load time,
//                 geometry memory and peak RSS are printed and in the scene's name.
//   "fog-box":    assets/fog-box (scripts/make_fog_box.py): the Cornell box filled with fog, lit by its ceiling light
//                 and a point lamp inside (distance, equiangular and phase sampling; docs/media.md).
// The scene named `keyword`, or nothing when it is not a generator keyword. Throws pv::Error if the built-in
// Cornell box it builds on cannot be loaded.
std::optional<Scene> generated_scene(const std::string& keyword);

// Appends a sphere of centre c and radius r, displaced radially by a smooth pattern of relative amplitude `amp`,
// as a (2 * n_phi * (n_theta - 1))-triangle grid with shared vertices, on material `material`.
void add_displaced_sphere(Scene& scene, vec3 c, float r, float amp, int n_theta, int n_phi, uint32_t material);

}  // namespace pv
