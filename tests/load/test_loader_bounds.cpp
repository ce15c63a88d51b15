// test_loader_bounds.cpp: the numeric bounds a scene file states are the bounds it applies (issue 41 item 5).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/load/scene_file.h"

namespace pv {
// The scene file documents "ior" in [0.001, 1000]: both ends are accepted (0.001 as a double is below the float
// 1e-3f the bound was compared with as a double, so the lower end itself was refused), just outside is refused.
TEST(LoaderBounds, SceneFileIorBoundsAreInclusive) {
    const std::string dir = std::filesystem::path(builtin_scene_path()).parent_path().string();
    for (const char* ior : {"0.001", "1000"}) {
        const std::string json = std::string(R"({"obj": "cornell-box.obj", "materials": {"white": )") +
                                 R"({"type": "metallic-roughness", "ior": )" + ior + "}}}";
        EXPECT_NO_THROW(load_scene_json_text(json, dir + "/ior.json")) << "ior " << ior;
    }
    for (const char* ior : {"0.0009", "1000.5"}) {
        const std::string json = std::string(R"({"obj": "cornell-box.obj", "materials": {"white": )") +
                                 R"({"type": "metallic-roughness", "ior": )" + ior + "}}}";
        EXPECT_THROW(load_scene_json_text(json, dir + "/ior.json"), std::exception) << "ior " << ior;
    }
}
}  // namespace pv
