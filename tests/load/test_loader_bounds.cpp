// test_loader_bounds.cpp: the numeric bounds a scene file states are the bounds it applies (issue 41 item 5).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/base/error.h"
#include "core/load/gltf_loader.h"
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

namespace {
// The message a refused file gets; "" if it loads.
template <class F>
std::string refusal(F&& load) {
    try {
        load();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// A glTF whose root object also holds `member` (an "extras" or a top-level list).
std::string gltf_with(const std::string& member) { return R"({"asset": {"version": "2.0"}, )" + member + "}"; }

void expect_refused(const std::string& text, const std::string& pointer, const std::string& what) {
    const std::string e = refusal([&] { load_gltf_from_memory(text, "hostile.gltf"); });
    EXPECT_EQ(e.rfind("hostile.gltf: " + pointer, 0), 0u) << e.substr(0, 300);
    EXPECT_NE(e.find(what), std::string::npos) << e.substr(0, 300);
    EXPECT_EQ(e.find('\n'), std::string::npos);
    EXPECT_LT(e.size(), 400u);
}
}  // namespace

// Issue 41 item 4: the JSON's shape is bounded before nlohmann or tinygltf parse it (both recurse per nesting level:
// 200,000 nested arrays overflowed the stack and killed the process; a few MB of nulls or empty nodes cost GBs).
TEST(LoaderBounds, DeeplyNestedGltfJsonIsRefusedInOneLine) {
    const size_t depth = 200000;
    expect_refused(
        gltf_with(R"("extras": )" + std::string(depth, '[') + std::string(depth, ']')),
        "/extras" +
            [] {
                std::string p;
                for (int i = 0; i < 63; ++i) p += "/0";
                return p;
            }(),
        "nested more than 64 levels deep");
    std::string objects;
    for (size_t i = 0; i < depth; ++i) objects += R"({"a": )";
    objects += "1" + std::string(depth, '}');
    const std::string e = refusal([&] { load_gltf_from_memory(gltf_with(R"("extras": )" + objects), "deep.gltf"); });
    EXPECT_EQ(e.rfind("deep.gltf: /extras/a/a/a/", 0), 0u) << e.substr(0, 300);
    EXPECT_NE(e.find("nested more than 64 levels deep"), std::string::npos) << e.substr(0, 300);
    // The .glb form's JSON chunk is scanned the same way.
    std::string json = gltf_with(R"("extras": )" + std::string(depth, '[') + std::string(depth, ']'));
    json.resize((json.size() + 3) / 4 * 4, ' ');
    std::string glb = "glTF";
    auto u32 = [&glb](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(uint32_t(20 + json.size()));
    u32(uint32_t(json.size()));
    u32(0x4E4F534Au);
    glb += json;
    const std::string g = refusal([&] { load_gltf_from_memory(glb, "deep.glb"); });
    EXPECT_NE(g.find("deep.glb: /extras/0/0/"), std::string::npos) << g.substr(0, 300);
}

TEST(LoaderBounds, HugeGltfArraysAreRefusedBeforeTheParse) {
    std::string nulls = R"("extras": [)";
    for (size_t i = 0; i < (size_t(1) << 22) + 1; ++i) nulls += "null,";
    nulls.back() = ']';
    expect_refused(gltf_with(nulls), "/extras/4194304: ", "an array of more than 4194304 elements");
    std::string nodes = R"("nodes": [)";
    for (size_t i = 0; i < 1000000; ++i) nodes += "{},";
    nodes.back() = ']';
    expect_refused(gltf_with(nodes), "/nodes/262144: ", "an array of more than 262144 elements");
    // The total: two arrays within the per-array bound, more than 2^23 values in all (the second one past it).
    std::string many = R"("extras": [)";
    for (int a = 0; a < 2; ++a) {
        many += a ? ",[" : "[";
        for (size_t i = 0; i < (size_t(1) << 22) - 1; ++i) many += "0,";
        many += "0]";
    }
    many += "]";
    expect_refused(gltf_with(many), "/extras/1/", "more than 8388608 JSON values");
}

// A file within the bounds still loads: the same list lengths just under them are not refused by the scan (the
// loader then refuses the empty nodes' file for other reasons or loads it).
TEST(LoaderBounds, GltfJsonWithinTheBoundsIsNotRefusedByTheScan) {
    std::string nodes = R"("scene": 0, "scenes": [{"nodes": [0]}], "nodes": [)";
    for (size_t i = 0; i < (size_t(1) << 18); ++i) nodes += "{},";
    nodes.back() = ']';
    std::string deep = R"("extras": )" + std::string(63, '[') + std::string(63, ']');
    EXPECT_EQ(refusal([&] { load_gltf_from_memory(gltf_with(nodes + ", " + deep), "ok.gltf"); }), "");
}

TEST(LoaderBounds, DeeplyNestedSceneFileIsRefusedInOneLine) {
    const std::string dir = std::filesystem::path(builtin_scene_path()).parent_path().string();
    const std::string json =
        R"({"obj": "cornell-box.obj", "extras": )" + std::string(200000, '[') + std::string(200000, ']') + "}";
    const std::string e = refusal([&] { load_scene_json_text(json, dir + "/deep.json"); });
    EXPECT_EQ(e.rfind(dir + "/deep.json: /extras/0/0/", 0), 0u) << e.substr(0, 300);
    EXPECT_NE(e.find("nested more than 64 levels deep"), std::string::npos) << e.substr(0, 300);
}
}  // namespace pv
