// tests/fuzz/fuzz_draco.cpp: libFuzzer entry point over KHR_draco_mesh_compression (core/load/gltf_compression.cpp:
// the checks, Draco's decoder, attribute ids and component counts), then the loader's accessors, the Embree BVH
// and a few rays. The input is the Draco stream, wrapped in a .glb whose primitive names POSITION (id 0), NORMAL
// (id 1) and TEXCOORD_0 (id 2), as tests/data/gltf-compressed/draco.gltf does. Bad input must end in pv::Error or a
// loaded scene, never a crash. Seeds: tests/fuzz/corpus-draco (tests/fuzz/make_compressed_corpus.py).
// (Debian's libdraco is not instrumented: reads inside Draco itself are not checked by ASan here.)
#include <cstdint>
#include <string>

#include "core/base/error.h"
#include "core/load/gltf_loader.h"
#include "tests/fuzz/fuzz_compressed_glb.h"
#include "tests/fuzz/fuzz_scene_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0 || size > (1u << 16)) return 0;
    const std::string bin(reinterpret_cast<const char*>(data), size);
    const std::string json =
        R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],)"
        R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],"meshes":[{"primitives":[{)"
        R"("attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3,"extensions":{)"
        R"("KHR_draco_mesh_compression":{"bufferView":0,"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}}}}]}],)"
        R"("accessors":[{"componentType":5126,"count":3,"type":"VEC3"},{"componentType":5126,"count":3,"type":"VEC3"},)"
        R"({"componentType":5126,"count":3,"type":"VEC2"},{"componentType":5125,"count":3,"type":"SCALAR"}],)"
        R"("bufferViews":[{"buffer":0,"byteLength":)" +
        std::to_string(size) + R"(}],"buffers":[{"byteLength":)" + std::to_string(size) + "}]}";
    pv::Scene scene;
    try {
        scene = pv::load_gltf_from_memory(pv_fuzz::glb(json, bin), "/nonexistent-fuzz-folder/fuzz.glb");
    } catch (const pv::Error&) {
        return 0;
    }
    pv_fuzz::check_loaded_scene(scene);
    pv_fuzz::trace_and_sample(scene);
    return 0;
}
