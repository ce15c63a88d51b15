// tests/fuzz/fuzz_scene_checks.h: what the fuzzers of the scene loaders (fuzz_obj, fuzz_gltf) check on a scene a
// loader returned: what every loader promises (indices in range, finite vertices, per-triangle arrays complete),
// then the Embree BVH build, a handful of closest-hit and occlusion rays through the scene's bounds and a light
// sample under each light sampler, as rendering would. A broken promise aborts (libFuzzer reports it).
#pragma once

#include <cstdlib>

#include "core/base/error.h"
#include "core/render/accel.h"
#include "core/render/lights.h"

namespace pv_fuzz {

inline void check_loaded_scene(const pv::Scene& scene) {
    const size_t nt = scene.triangles.size();
    if (scene.material_ids.size() != nt) std::abort();
    if (!scene.normal_indices.empty() && scene.normal_indices.size() != nt) std::abort();
    if (!scene.uv_indices.empty() && scene.uv_indices.size() != nt) std::abort();
    if (!scene.uv1_indices.empty() && scene.uv1_indices.size() != nt) std::abort();
    if (!scene.color_indices.empty() && scene.color_indices.size() != nt) std::abort();
    auto in_range = [](const std::vector<pv::uvec3>& indices, size_t i, int k, size_t n) {
        return indices.empty() || indices[i][k] == pv::kNoIndex || indices[i][k] < n;
    };
    for (size_t i = 0; i < nt; ++i) {
        const pv::uvec3 t = scene.triangles[i];
        for (int k = 0; k < 3; ++k) {
            if (t[k] >= scene.positions.size() || !pv::is_finite(scene.positions[t[k]])) std::abort();
            if (!in_range(scene.normal_indices, i, k, scene.normals.size()) ||
                !in_range(scene.uv_indices, i, k, scene.uvs.size()) ||
                !in_range(scene.uv1_indices, i, k, scene.uvs1.size()) ||
                !in_range(scene.color_indices, i, k, scene.colors.size()))
                std::abort();
        }
        if (scene.material_ids[i] >= scene.materials.size()) std::abort();
    }
    for (const pv::Material& m : scene.materials)
        for (uint32_t tex : {m.base_color_texture, m.alpha_texture, m.emissive_texture, m.metallic_roughness_texture,
                             m.normal_texture})
            if (tex != pv::kNoIndex && tex >= scene.textures.size()) std::abort();
    if (!pv::is_finite(scene.camera.eye) || !pv::is_finite(scene.camera.target)) std::abort();
}

inline void trace_and_sample(const pv::Scene& scene) {
    try {
        const pv::Accel accel(scene);
        pv::LightSet lights(scene, scene.materials);
        pv::vec3 lo, hi;
        scene.bounds(lo, hi);
        const pv::vec3 centre = 0.5f * (lo + hi);
        const pv::vec3 dirs[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-0.6f, 0.48f, 0.64f}};
        for (const pv::vec3& d : dirs) {
            pv::Ray r;
            r.o = centre - d * (1.f + pv::max_component(hi - lo));
            r.d = d;
            pv::Hit hit;
            if (accel.intersect(r, hit) && hit.prim >= scene.triangles.size()) std::abort();
            accel.occluded(r);
            // Both light samplers: by power, and the light tree (built on first use).
            for (const auto kind : {pv::LightSamplerKind::Power, pv::LightSamplerKind::Tree}) {
                lights.set_sampler(kind);
                pv::LightSample ls;
                if (lights.sample(centre, -d, 0.5f, pv::vec2(0.3f, 0.6f), ls) && !(ls.pdf > 0.f)) std::abort();
            }
        }
    } catch (const pv::Error&) {
    }
}

}  // namespace pv_fuzz
