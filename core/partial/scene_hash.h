// core/partial/scene_hash.h: the content hash that tells whether two partial renders (or a part and the scene given
// to --resume) come from the same scene.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/scene/bsdf.h"
#include "core/scene/scene.h"

namespace pv {

// Content hash of what the renderer draws from: triangles, normals, UVs, material ids, materials as edited,
// textures (including the environment map) and the environment's settings. Not the file names.
// fog: the global medium as traced (the scene's unless edited in the viewer).
uint64_t scene_hash(const Scene& scene, const std::vector<Material>& materials, const EnvironmentSettings& env,
                    const HomogeneousMedium& fog);
inline uint64_t scene_hash(const Scene& scene, const std::vector<Material>& materials, const EnvironmentSettings& env) {
    return scene_hash(scene, materials, env, scene.fog);
}
// The hash as written in pathview:scene_hash: 16 lowercase hex digits.
std::string hash_hex(uint64_t hash);

}  // namespace pv
