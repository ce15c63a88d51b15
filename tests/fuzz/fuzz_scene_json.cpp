// tests/fuzz/fuzz_scene_json.cpp: libFuzzer entry point over the JSON scene reader (load_scene_json_text): parsing,
// validation of every key, then the OBJ, material overrides, bookmarks and environment maps it names. Next to the
// fuzzed file lie a.obj (one triangle), lit.obj (an emitter with material "m") and sky.hdr (a small RLE map), the
// names the seeds in tests/fuzz/corpus-json use. Bad input must end in pv::Error or a scene whose values are the
// validated ones (finite camera, non-negative lighting), never a crash or a sanitizer report.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/base/error.h"
#include "core/image/image_io.h"
#include "core/load/scene_file.h"

namespace {
std::string g_dir;

void put(const std::string& name, const std::string& text) {
    std::ofstream(g_dir + "/" + name, std::ios::binary) << text;
}

std::string sky_hdr() {
    std::string s = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n";
    for (int y = 0; y < 4; ++y) {
        s += std::string("\x02\x02\x00\x08", 4);
        for (int k = 0; k < 4; ++k) s += std::string(1, char(128 + 8)) + char(k == 3 ? 128 : 60 + 10 * y);
    }
    return s;
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    pv::set_image_limits(pv::ImageLimits{4'000'000});
    g_dir = (std::filesystem::temp_directory_path() / ("pathview_fuzz_json_" + std::to_string(::getpid()))).string();
    std::filesystem::create_directories(g_dir);
    put("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    put("lit.obj", "mtllib lit.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl m\nf 1 2 3\nf 1 2 4\n");
    put("lit.mtl", "newmtl m\nKd 0.5 0.5 0.5\nKe 1 1 1\n");
    put("sky.hdr", sky_hdr());
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > (1u << 16)) return 0;
    const std::string text(reinterpret_cast<const char*>(data), size);
    pv::Scene scene;
    try {
        scene = pv::load_scene_json_text(text, g_dir + "/fuzz.json");
    } catch (const pv::Error&) {
        return 0;
    }
    // What validation promises: the ranges of the CLI.
    const pv::CameraDesc& c = scene.camera;
    if (!pv::is_finite(c.eye) || !pv::is_finite(c.target) || !(c.vfov_deg >= 0.01f && c.vfov_deg <= 179.f) ||
        !(c.aperture >= 0.f) || !(c.focus_distance >= 0.f))
        std::abort();
    if (!(scene.environment.strength >= 0.f) || !pv::is_finite(scene.environment.sun_irradiance) ||
        !(scene.environment.sun_irradiance.x >= 0.f) || !(scene.environment.sun_angular_radius_deg >= 0.01f) ||
        !pv::is_finite(scene.environment.background))
        std::abort();
    for (const pv::Material& m : scene.materials)
        if (!pv::is_finite(m.emission)) std::abort();
    for (const pv::Portal& p : scene.portals) {
        const pv::vec3 n = glm::cross(p.edge1, p.edge2);
        if (!pv::is_finite(p.corner) || !(glm::dot(n, n) > 0.f) || !std::isfinite(glm::dot(n, n))) std::abort();
    }
    return 0;
}
