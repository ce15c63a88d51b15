// tests/load/test_gltf_compressed.cpp: compressed and quantized glTF (core/load/gltf_compression.h) on the files of
// tests/data/gltf-compressed (scripts/make_compressed_gltf.sh: Draco's encoder API, gltfpack): each loads to the
// triangles of its uncompressed original within the dequantization rounding of its positions; malformed compressed
// data (truncated streams, counts past a buffer, unknown attribute ids, decoded sizes over the budget) ends in one
// line naming the file and the JSON pointer; the compressed, instanced showcase (assets/compressed-instanced) loads.
// Test kinds: unit; regression: UntrustedCompressed UntrustedWebp
#include <gtest/gtest.h>
#include <webp/encode.h>

#include <algorithm>
#include <cfloat>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/base/error.h"
#include "core/load/gltf_loader.h"
#include "core/scene/texture.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const std::string kData = std::string(PATHVIEW_TEST_DATA) + "/gltf-compressed";

std::string read(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

struct Tri {
    vec3 v[3];
};

std::vector<Tri> triangles(const Scene& s) {
    std::vector<Tri> out;
    for (const uvec3& t : s.triangles) out.push_back({{s.positions[t.x], s.positions[t.y], s.positions[t.z]}});
    return out;
}

// Every triangle of `got` matches a distinct triangle of `want` (same vertices in the same cyclic order) within
// `tol` per coordinate, and the counts agree.
void expect_same_triangles(const std::vector<Tri>& want, const std::vector<Tri>& got, float tol) {
    ASSERT_EQ(want.size(), got.size());
    std::vector<uint8_t> used(want.size(), 0);
    auto close = [&](vec3 a, vec3 b) { return max_component(glm::abs(a - b)) <= tol; };
    size_t unmatched = 0;
    for (const Tri& g : got) {
        bool found = false;
        for (size_t i = 0; i < want.size() && !found; ++i) {
            if (used[i]) continue;
            for (int r = 0; r < 3 && !found; ++r)
                if (close(g.v[0], want[i].v[r]) && close(g.v[1], want[i].v[(r + 1) % 3]) &&
                    close(g.v[2], want[i].v[(r + 2) % 3])) {
                    used[i] = 1;
                    found = true;
                }
        }
        if (!found) ++unmatched;
    }
    EXPECT_EQ(unmatched, 0u) << "of " << got.size() << " triangles, within " << tol;
}

// Positions quantized to 14 bits over the mesh's bounding box (both gltfpack's default -vp 14 and the Draco file's
// setting): each coordinate within half a step, extent / (2^14 - 1) / 2, plus float rounding of the dequantization
// (a few ulps of the extent).
float quantization_tolerance(const Scene& original) {
    vec3 lo(FLT_MAX), hi(-FLT_MAX);
    for (const vec3& p : original.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const float extent = max_component(hi - lo);
    return 0.5f * extent / 16383.f + 8.f * FLT_EPSILON * extent;
}

TEST(GltfCompressed, EachLoadsToTheOriginalsTriangles) {
    const Scene original = load_gltf(kData + "/original.gltf");
    ASSERT_EQ(original.triangles.size(), 960u);
    const float tol = quantization_tolerance(original);
    for (const char* name : {"draco.gltf", "quantized.gltf", "quantized_vpn.gltf", "meshopt.gltf", "meshopt.glb"}) {
        SCOPED_TRACE(name);
        Scene s;
        ASSERT_NO_THROW(s = load_gltf(kData + "/" + name));
        expect_same_triangles(triangles(original), triangles(s), tol);
        EXPECT_FALSE(s.normal_indices.empty());
    }
}

// The showcase (scripts/make_compressed_showcase.sh: gltfpack -c of the test mesh placed by 400 nodes, and a ground
// quad): every instance is there, each with the mesh's 960 triangles, and nothing was dropped.
TEST(GltfCompressed, ShowcaseLoadsEveryInstance) {
    const Scene s = load_gltf(std::string(PATHVIEW_ASSETS) + "/compressed-instanced/scene.glb");
    EXPECT_EQ(s.triangles.size(), 400u * 960u + 2u);
    EXPECT_EQ(s.stats.dropped_nonfinite, 0u);
    EXPECT_EQ(s.stats.dropped_degenerate, 0u);
    EXPECT_TRUE(s.has_camera);
    EXPECT_EQ(s.punctual_lights.size(), 1u);
}

// The file's JSON changed by `edit`, written next to copies of its .bin files; loading it must fail with one line
// naming the file and containing `pointer` and `words`.
void expect_refused(const std::string& name, const std::function<void(json&)>& edit, const std::string& pointer,
                    const std::string& words) {
    test::TestDir dir("gltfc");
    for (const auto& e : fs::directory_iterator(kData))
        if (e.path().extension() == ".bin") fs::copy_file(e.path(), dir.path / e.path().filename());
    json j = json::parse(read(kData + "/" + name));
    edit(j);
    const std::string path = dir.write(name, j.dump());
    try {
        load_gltf(path);
        ADD_FAILURE() << name << ": loaded; expected a refusal at " << pointer;
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
        EXPECT_NE(msg.find(pointer), std::string::npos) << msg;
        EXPECT_NE(msg.find(words), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

const std::string kDraco = "/meshes/0/primitives/0/extensions/KHR_draco_mesh_compression";

TEST(UntrustedCompressed, DracoTruncatedStream) {
    expect_refused(
        "draco.gltf",
        [](json& j) { j["bufferViews"][0]["byteLength"] = j["bufferViews"][0]["byteLength"].get<int>() / 2; }, kDraco,
        "malformed or truncated");
}

TEST(UntrustedCompressed, DracoWrongAttributeId) {
    expect_refused(
        "draco.gltf",
        [](json& j) {
            j["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] = 9;
        },
        kDraco + "/attributes/POSITION", "no attribute with id 9");
}

TEST(UntrustedCompressed, DracoViewPastTheBuffer) {
    expect_refused(
        "draco.gltf", [](json& j) { j["bufferViews"][0]["byteOffset"] = 64; }, "/bufferViews/0",
        "past the end of buffer 0");
}

TEST(UntrustedCompressed, DracoComponentsDifferFromTheAccessor) {
    expect_refused(
        "draco.gltf", [](json& j) { j["accessors"][2]["type"] = "VEC3"; }, kDraco + "/attributes/TEXCOORD_0",
        "components");
}

const std::string kMeshopt = "/bufferViews/0/extensions/EXT_meshopt_compression";

TEST(UntrustedCompressed, MeshoptTruncatedStream) {
    expect_refused(
        "meshopt.gltf",
        [](json& j) { j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 300; }, kMeshopt,
        "malformed or truncated");
}

TEST(UntrustedCompressed, MeshoptSourcePastTheBuffer) {
    expect_refused(
        "meshopt.gltf",
        [](json& j) { j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteOffset"] = 5000; }, kMeshopt,
        "past the end of buffer 0");
}

TEST(UntrustedCompressed, MeshoptCountPastTheView) {
    expect_refused(
        "meshopt.gltf", [](json& j) { j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 100000; },
        kMeshopt + "/count", "past the buffer view's byteLength");
}

TEST(UntrustedCompressed, MeshoptDecodedSizeOverTheBudget) {
    // 2^40 bytes declared: refused before anything is allocated (the test would otherwise die of memory).
    expect_refused(
        "meshopt.gltf",
        [](json& j) {
            j["bufferViews"][0]["byteLength"] = uint64_t(1) << 40;
            j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = uint64_t(1) << 37;
        },
        kMeshopt, "budget");
}

TEST(UntrustedCompressed, MeshoptBadStrideAndMode) {
    expect_refused(
        "meshopt.gltf", [](json& j) { j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteStride"] = 6; },
        kMeshopt + "/byteStride", "multiple of 4");
    expect_refused(
        "meshopt.gltf",
        [](json& j) { j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["mode"] = "POINTS"; },
        kMeshopt + "/mode", "expected ATTRIBUTES");
}

// ---- EXT_texture_webp ----

// A lossless WebP of 3 x 2 RGBA pixels (libwebp's encoder).
std::string webp_3x2(const uint8_t rgba[24]) {
    uint8_t* out = nullptr;
    const size_t n = WebPEncodeLosslessRGBA(rgba, 3, 2, 12, &out);
    std::string s(reinterpret_cast<const char*>(out), n);
    WebPFree(out);
    return s;
}

const uint8_t kPixels[24] = {255, 0,  0,  255, 0,   255, 0,  255, 0,   0,   255, 255,
                             10,  20, 30, 128, 200, 100, 50, 255, 255, 255, 255, 1};

TEST(GltfWebp, DecodesLikeTheSamePixelsAsTga) {
    // The same pixels as an uncompressed 32-bit TGA (top-left origin): the texels must be equal.
    std::string tga(18, '\0');
    tga[2] = 2, tga[12] = 3, tga[14] = 2, tga[16] = 32, tga[17] = 0x28;
    for (int i = 0; i < 6; ++i)
        tga += std::string{char(kPixels[4 * i + 2]), char(kPixels[4 * i + 1]), char(kPixels[4 * i]),
                           char(kPixels[4 * i + 3])};
    const Texture a = Texture::decode(webp_3x2(kPixels), "a.webp", false, nullptr);
    const Texture b = Texture::decode(tga, "b.tga", false, nullptr);
    ASSERT_EQ(a.width(), 3);
    ASSERT_EQ(a.height(), 2);
    const std::vector<vec4> ta = a.texels(), tb = b.texels();
    ASSERT_EQ(ta.size(), 6u);
    ASSERT_EQ(tb.size(), 6u);
    for (size_t i = 0; i < 6; ++i) EXPECT_EQ(ta[i], tb[i]) << i;
}

TEST(GltfWebp, ATextureThroughTheExtensionLoads) {
    test::TestDir dir("gltfw");
    fs::copy_file(kData + "/original.bin", dir.path / "original.bin");
    dir.write("t.webp", webp_3x2(kPixels));
    json j = json::parse(read(kData + "/original.gltf"));
    j["images"] = {{{"uri", "t.webp"}, {"mimeType", "image/webp"}}};
    j["textures"] = {{{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}}};
    j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    j["extensionsUsed"] = {"EXT_texture_webp"};
    j["extensionsRequired"] = {"EXT_texture_webp"};
    const Scene s = load_gltf(dir.write("webp.gltf", j.dump()));
    ASSERT_LT(s.materials[0].base_color_texture, s.textures.size());
    EXPECT_EQ(s.textures[s.materials[0].base_color_texture].width(), 3);
    EXPECT_EQ(s.textures[s.materials[0].base_color_texture].height(), 2);
    for (const std::string& w : s.warnings) EXPECT_EQ(w.find("EXT_texture_webp"), std::string::npos) << w;
}

TEST(UntrustedWebp, FileIsNotReadPastItsRiffLength) {
    // A WebP file names its own length (RIFF); a file grown to 1 GiB (sparse) is refused from its first bytes, not
    // read (it was read whole before being decoded), and the same file at its length loads.
    test::TestDir dir("gltfw");
    const std::string w = webp_3x2(kPixels);
    const std::string path = dir.write("big.webp", w);
    fs::resize_file(path, uint64_t(1) << 30);
    try {
        Texture::load(path);
        ADD_FAILURE() << "a 1 GiB file with a " << w.size() << "-byte WebP in front was read";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": the file is 1073741824 bytes; the limit for ", 0), 0u)
            << e.what();
    }
    fs::resize_file(path, w.size());
    EXPECT_EQ(Texture::load(path).width(), 3);
}

TEST(UntrustedWebp, HeaderOverTheBudgetIsRefusedBeforeDecoding) {
    // The VP8L header's 14-bit width and height set to 16384 x 16384 (268 MP, over the 135-MP budget) in a file of
    // a few dozen bytes: refused from the header, naming the file.
    std::string w = webp_3x2(kPixels);
    ASSERT_EQ(w.compare(12, 4, "VP8L"), 0);
    ASSERT_EQ(uint8_t(w[20]), 0x2f);
    uint32_t bits = 0;
    std::memcpy(&bits, w.data() + 21, 4);
    bits = (bits & ~0x0FFFFFFFu) | 16383u | (16383u << 14);
    std::memcpy(w.data() + 21, &bits, 4);
    try {
        Texture::decode(w, "big.webp", false, nullptr);
        ADD_FAILURE() << "a 16384 x 16384 WebP header was decoded";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.rfind("big.webp: ", 0), 0u) << m;
        EXPECT_NE(m.find("16384"), std::string::npos) << m;
    }
    // Truncated data: one line, no crash.
    EXPECT_THROW(Texture::decode(webp_3x2(kPixels).substr(0, 30), "cut.webp", false, nullptr), Error);
}

}  // namespace
}  // namespace pv
