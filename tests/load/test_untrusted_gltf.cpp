// tests/load/test_untrusted_gltf.cpp: the glTF fuzzer's seed corpus (tests/fuzz/corpus-gltf, written by
// make_gltf_corpus.py) is valid: every seed loads, its .gltf and .glb forms give the same scene, and the materials
// seed's embedded PNG is decoded (through Texture::decode) into the textures its materials use.
// Test kinds: regression
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/load/gltf_loader.h"

namespace pv {
namespace {

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(UntrustedGltf, EverySeedLoadsAndItsGltfAndGlbFormsAgree) {
    const std::string dir = std::string(PATHVIEW_FUZZ_DIR) + "/corpus-gltf/";
    for (const char* name : {"seed_nodes", "seed_accessors", "seed_materials"}) {
        const Scene a = load_gltf_from_memory(slurp(dir + name + ".gltf"), name);
        const Scene b = load_gltf_from_memory(slurp(dir + name + ".glb"), name);
        EXPECT_GT(a.triangle_count(), 0u) << name;
        EXPECT_EQ(a.triangles, b.triangles) << name;
        EXPECT_EQ(a.positions, b.positions) << name;
        EXPECT_EQ(a.uvs, b.uvs) << name;
        EXPECT_EQ(a.materials.size(), b.materials.size()) << name;
        EXPECT_EQ(a.textures.size(), b.textures.size()) << name;
        EXPECT_EQ(a.warnings, b.warnings) << name;
    }
    const Scene m = load_gltf_from_memory(slurp(dir + "seed_materials.glb"), "seed_materials.glb");
    ASSERT_EQ(m.materials.size(), 3u);
    EXPECT_NE(m.materials[0].base_color_texture, kNoIndex);  // masked: factor x texture, alpha cut at 0.4
    EXPECT_EQ(m.materials[0].alpha_texture, m.materials[0].base_color_texture);
    EXPECT_NE(m.materials[1].emissive_texture, kNoIndex);
    EXPECT_EQ(m.materials[1].emission, vec3(12.f, 0.8f * 12.f, 0.5f * 12.f));
    EXPECT_NE(m.materials[2].alpha_texture, kNoIndex);  // BLEND with alpha 0.5: stochastic
    for (const std::string& w : m.warnings) ADD_FAILURE() << w;
}

}  // namespace
}  // namespace pv
