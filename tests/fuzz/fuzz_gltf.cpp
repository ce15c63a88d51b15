// tests/fuzz/fuzz_gltf.cpp: libFuzzer entry point over pathview's glTF import path: load_gltf_from_memory (.glb
// when the bytes start with "glTF", else JSON text: the pre-pass, tinygltf, bounds-checked accessors, the node
// tree, embedded images through Texture::decode, materials, cameras), then the Embree BVH build and a handful of
// rays, as rendering would. Bad input must end in pv::Error or a loaded scene, never a crash, an ASan/UBSan report
// or an index out of range. The name places the file in a folder that does not exist, so relative URIs (.bin,
// images) find nothing. (libtinygltf itself is Debian's uninstrumented build: its own reads are not checked here.)
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/accel.h"
#include "core/error.h"
#include "core/gltf_loader.h"
#include "core/lights.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > (1u << 16)) return 0;  // keep inputs small: the interesting bugs are in the parsing
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    pv::Scene scene;
    try {
        scene = pv::load_gltf_from_memory(bytes, "/nonexistent-fuzz-folder/fuzz.gltf");
    } catch (const pv::Error&) {
        return 0;
    }
    // What the loader promises: indices in range, finite non-degenerate triangles, per-triangle arrays complete.
    const size_t nt = scene.triangles.size();
    if (scene.material_ids.size() != nt) std::abort();
    if (!scene.normal_indices.empty() && scene.normal_indices.size() != nt) std::abort();
    if (!scene.uv_indices.empty() && scene.uv_indices.size() != nt) std::abort();
    if (!scene.uv1_indices.empty() && scene.uv1_indices.size() != nt) std::abort();
    if (!scene.color_indices.empty() && scene.color_indices.size() != nt) std::abort();
    for (size_t i = 0; i < nt; ++i) {
        const pv::uvec3 t = scene.triangles[i];
        for (int k = 0; k < 3; ++k) {
            if (t[k] >= scene.positions.size() || !pv::is_finite(scene.positions[t[k]])) std::abort();
            if (!scene.normal_indices.empty() && scene.normal_indices[i][k] != pv::kNoIndex &&
                scene.normal_indices[i][k] >= scene.normals.size())
                std::abort();
            if (!scene.uv_indices.empty() && scene.uv_indices[i][k] != pv::kNoIndex &&
                scene.uv_indices[i][k] >= scene.uvs.size())
                std::abort();
            if (!scene.uv1_indices.empty() && scene.uv1_indices[i][k] != pv::kNoIndex &&
                scene.uv1_indices[i][k] >= scene.uvs1.size())
                std::abort();
            if (!scene.color_indices.empty() && scene.color_indices[i][k] != pv::kNoIndex &&
                scene.color_indices[i][k] >= scene.colors.size())
                std::abort();
        }
        if (scene.material_ids[i] >= scene.materials.size()) std::abort();
    }
    for (const pv::Material& m : scene.materials)
        for (uint32_t tex : {m.base_color_texture, m.alpha_texture, m.emissive_texture})
            if (tex != pv::kNoIndex && tex >= scene.textures.size()) std::abort();
    if (!pv::is_finite(scene.camera.eye) || !pv::is_finite(scene.camera.target)) std::abort();
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
    return 0;
}
