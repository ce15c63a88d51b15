// tests/fuzz/fuzz_meshopt.cpp: libFuzzer entry point over EXT_meshopt_compression (core/load/gltf_compression.cpp:
// the checks, meshoptimizer's vertex and index decoders and filters), then the loader's accessors, the Embree BVH
// and a few rays. The first 5 bytes choose mode (ATTRIBUTES, TRIANGLES, INDICES), filter (NONE, OCTAHEDRAL,
// QUATERNION, EXPONENTIAL), byteStride and count; the rest is the compressed stream, behind 36 bytes of three plain
// float positions that the index modes index. Bad input must end in pv::Error or a loaded scene, never a crash.
// Seeds: tests/fuzz/corpus-meshopt (tests/fuzz/make_compressed_corpus.py, from tests/data/gltf-compressed).
#include <cstdint>
#include <cstring>
#include <string>

#include "core/base/error.h"
#include "core/load/gltf_loader.h"
#include "tests/fuzz/fuzz_compressed_glb.h"
#include "tests/fuzz/fuzz_scene_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 5 || size > (1u << 16)) return 0;
    static const char* kModes[] = {"ATTRIBUTES", "TRIANGLES", "INDICES"};
    static const char* kFilters[] = {"NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"};
    const int mode = data[0] % 3;
    const char* filter = kFilters[data[1] % 4];
    const unsigned stride = data[2];
    const unsigned count = unsigned(data[3]) | unsigned(data[4]) << 8;
    const std::string stream(reinterpret_cast<const char*>(data) + 5, size - 5);
    const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::string bin = std::string(reinterpret_cast<const char*>(tri), 36) + stream;
    const unsigned decoded = count * stride;
    std::string accessor;
    std::string attributes;
    if (mode == 0) {
        // Positions from the decoded view: floats when the stride holds 12 bytes, else 16-bit or 8-bit integers
        // (KHR_mesh_quantization).
        const int type = stride >= 12 ? 5126 : stride >= 6 ? 5123 : 5121;
        accessor = R"({"bufferView":1,"componentType":)" + std::to_string(type) + R"(,"count":)" +
                   std::to_string(count) + R"(,"type":"VEC3"})";
        attributes = R"("attributes":{"POSITION":1})";
    } else {
        accessor = R"({"bufferView":1,"componentType":)" + std::string(stride == 2 ? "5123" : "5125") + R"(,"count":)" +
                   std::to_string(count) + R"(,"type":"SCALAR"})";
        attributes = R"("attributes":{"POSITION":0},"indices":1)";
    }
    const std::string json =
        R"({"asset":{"version":"2.0"},"extensionsUsed":["EXT_meshopt_compression","KHR_mesh_quantization"],)"
        R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],"meshes":[{"primitives":[{)" +
        attributes + R"(}]}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)" + accessor +
        R"(],"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":1,"byteLength":)" + std::to_string(decoded) +
        (mode == 0 ? R"(,"byteStride":)" + std::to_string(stride) : std::string()) +
        R"(,"extensions":{"EXT_meshopt_compression":{"buffer":0,"byteOffset":36,"byteLength":)" +
        std::to_string(stream.size()) + R"(,"byteStride":)" + std::to_string(stride) + R"(,"count":)" +
        std::to_string(count) + R"(,"mode":")" + kModes[mode] + R"(","filter":")" + filter +
        R"("}}}],"buffers":[{"byteLength":)" + std::to_string(bin.size()) + R"(},{"byteLength":)" +
        std::to_string(decoded) + R"(,"extensions":{"EXT_meshopt_compression":{"fallback":true}}}]})";
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
