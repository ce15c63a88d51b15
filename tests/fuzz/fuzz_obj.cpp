// tests/fuzz/fuzz_obj.cpp: libFuzzer entry point over pathview's OBJ import path: load_obj_from_string (pre-scan,
// tinyobjloader, validation), then the Embree BVH build and a handful of closest-hit and occlusion rays through
// the scene's bounds, as rendering would. Bad input must end in pv::Error or a loaded scene, never a crash,
// an ASan/UBSan report or a NaN in the loaded data.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/accel.h"
#include "core/error.h"
#include "core/lights.h"
#include "core/obj_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > (1u << 16)) return 0;  // keep inputs small: the interesting bugs are in the parsing
    const std::string text(reinterpret_cast<const char*>(data), size);
    pv::Scene scene;
    try {
        scene = pv::load_obj_from_string(text, "fuzz.obj");
    } catch (const pv::Error&) {
        return 0;
    }
    // What validation promises (core/obj_loader.h): indices in range, finite non-degenerate triangles.
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const pv::uvec3 t = scene.triangles[i];
        if (t.x >= scene.positions.size() || t.y >= scene.positions.size() || t.z >= scene.positions.size())
            std::abort();
        if (scene.material_ids[i] >= scene.materials.size()) std::abort();
        for (int k = 0; k < 3; ++k)
            if (!pv::is_finite(scene.positions[t[k]])) std::abort();
        if (!scene.normal_indices.empty())
            for (int k = 0; k < 3; ++k)
                if (scene.normal_indices[i][k] != pv::kNoIndex && scene.normal_indices[i][k] >= scene.normals.size())
                    std::abort();
    }
    try {
        const pv::Accel accel(scene);
        const pv::LightSet lights(scene, scene.materials);
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
            pv::LightSample ls;
            if (lights.sample(centre, -d, 0.5f, pv::vec2(0.3f, 0.6f), ls) && !(ls.pdf > 0.f)) std::abort();
        }
    } catch (const pv::Error&) {
    }
    return 0;
}
