// tests/fuzz/fuzz_obj.cpp: libFuzzer entry point over pathview's OBJ import path: load_obj_from_string (pre-scan,
// tinyobjloader, validation), then the Embree BVH build and a handful of closest-hit and occlusion rays through
// the scene's bounds, as rendering would. Bad input must end in pv::Error or a loaded scene, never a crash,
// an ASan/UBSan report or a NaN in the loaded data.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/base/error.h"
#include "core/load/obj_loader.h"
#include "tests/fuzz/fuzz_scene_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > (1u << 16)) return 0;  // keep inputs small: the interesting bugs are in the parsing
    const std::string text(reinterpret_cast<const char*>(data), size);
    pv::Scene scene;
    try {
        scene = pv::load_obj_from_string(text, "fuzz.obj");
    } catch (const pv::Error&) {
        return 0;
    }
    pv_fuzz::check_loaded_scene(scene);
    pv_fuzz::trace_and_sample(scene);
    return 0;
}
