// tests/fuzz/fuzz_gltf.cpp: libFuzzer entry point over pathview's glTF import path: load_gltf_from_memory (.glb
// when the bytes start with "glTF", else JSON text: the pre-pass, tinygltf, bounds-checked accessors, the node
// tree, embedded images through Texture::decode, materials, cameras), then the Embree BVH build and a handful of
// rays, as rendering would. Bad input must end in pv::Error or a loaded scene, never a crash, an ASan/UBSan report
// or an index out of range. The name places the file in a folder that does not exist, so relative URIs (.bin,
// images) find nothing. (libtinygltf itself is Debian's uninstrumented build: its own reads are not checked here.)
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/base/error.h"
#include "core/load/gltf_loader.h"
#include "tests/fuzz/fuzz_scene_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > (1u << 20)) return 0;  // up to 1 MiB (make test-fuzz: -max_len): large counts, deep nesting
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    pv::Scene scene;
    try {
        scene = pv::load_gltf_from_memory(bytes, "/nonexistent-fuzz-folder/fuzz.gltf");
    } catch (const pv::Error&) {
        return 0;
    }
    pv_fuzz::check_loaded_scene(scene);
    pv_fuzz::trace_and_sample(scene);
    return 0;
}
