// test_loader_bounds.cpp: the numeric bounds a scene file states are the bounds it applies (issue 41 item 5).
// Test kinds: regression
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "core/base/error.h"
#include "core/load/gltf_loader.h"
#include "core/load/scene_file.h"
#include "core/scene/bsdf_pbr.h"
#include "core/scene/texture.h"
#include "tests/support/temp_dir.h"

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

namespace {
// One triangle (positions (0,0,0), (1,0,0), (0,1,0) as a data URI) in scene 0, with `extra` members in the root.
std::string triangle_gltf(const std::string& extra) {
    return R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36,
                     "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}])" +
           extra + "}";
}
}  // namespace

// Issue 41 item 5: tinygltf 2.7 silently rendered scene 0 for a "scene" it could not use.
TEST(LoaderBounds, GltfSceneIndexOutOfRangeOrNotAnIntegerIsRefused) {
    EXPECT_EQ(refusal([&] { load_gltf_from_memory(triangle_gltf(R"(, "scene": 0, "materials": [{}])"), "s.gltf"); }),
              "");
    for (const char* index : {"1", "-1", "0.5", "\"0\"", "null", "4294967296"}) {
        const std::string e = refusal([&] {
            load_gltf_from_memory(triangle_gltf(std::string(R"(, "materials": [{}], "scene": )") + index), "s.gltf");
        });
        EXPECT_EQ(e.rfind("s.gltf: /scene: ", 0), 0u) << index << ": " << e;
        EXPECT_NE(e.find("expected an integer in [0, 1)"), std::string::npos) << index << ": " << e;
    }
}

// Issue 41 item 5: a .glb whose first buffer declares 0 bytes got tinygltf's raw "vector::_M_range_check" message.
TEST(LoaderBounds, GlbBufferOfZeroBytesIsRefusedInOneLine) {
    std::string json = R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 0}]})";
    json.resize((json.size() + 3) / 4 * 4, ' ');
    std::string glb = "glTF";
    auto u32 = [&glb](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(uint32_t(12 + 8 + json.size() + 8 + 12));
    u32(uint32_t(json.size()));
    u32(0x4E4F534Au);
    glb += json;
    u32(12);
    u32(0x004E4942u);
    glb += std::string(12, '\0');
    EXPECT_EQ(refusal([&] { load_gltf_from_memory(glb, "zero.glb"); }),
              "zero.glb: /buffers/0/byteLength: 0; a buffer holds at least one byte");
}

// Issue 41 item 5: KHR_materials_ior's "ior": 1e8 made every sample on the surface NaN (dropped: black, no word);
// it is clamped to the bound scene files apply (1000), with a warning naming the value's JSON pointer.
TEST(LoaderBounds, GltfIorAboveTheSceneFileBoundIsClampedWithAWarning) {
    for (const char* ior : {"1e8", "1e50", "1000.5"}) {
        const Scene s = load_gltf_from_memory(
            triangle_gltf(std::string(R"(, "extensionsUsed": ["KHR_materials_ior"], "materials": [{"extensions":
                {"KHR_materials_ior": {"ior": )") +
                          ior + "}}}]"),
            "ior.gltf");
        ASSERT_EQ(s.materials.size(), 1u);
        const auto* mr = std::get_if<MetallicRoughness>(&s.materials[0].bsdf);
        ASSERT_NE(mr, nullptr);
        EXPECT_EQ(mr->ior, 1000.f) << ior;
        ASSERT_EQ(s.warnings.size(), 1u) << ior;
        EXPECT_EQ(s.warnings[0].rfind("ior.gltf: /materials/0/extensions/KHR_materials_ior/ior: ", 0), 0u)
            << s.warnings[0];
        EXPECT_NE(s.warnings[0].find("clamped to 1000"), std::string::npos) << s.warnings[0];
    }
    const Scene s =
        load_gltf_from_memory(triangle_gltf(R"(, "extensionsUsed": ["KHR_materials_ior"], "materials": [{"extensions":
            {"KHR_materials_ior": {"ior": 1000}}}])"),
                              "ior.gltf");
    EXPECT_EQ(std::get<MetallicRoughness>(s.materials[0].bsdf).ior, 1000.f);
    EXPECT_TRUE(s.warnings.empty());
}

namespace {
// The process's peak resident memory so far, in bytes (a high-water mark: a test compares it before and after).
uint64_t peak_rss() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return uint64_t(u.ru_maxrss) * 1024;
}

// A 2x2 binary PPM followed by zeros up to 1 GiB (sparse: no disk used): its header needs 12 bytes of pixels.
std::string huge_ppm(const test::TestDir& dir) {
    const std::string path = dir.write("huge.ppm", std::string("P6\n2 2\n255\n") + std::string(12, '\x80'));
    std::filesystem::resize_file(path, uint64_t(1) << 30);
    return path;
}
}  // namespace

// Issue 41 item 5: an image named by a glTF uri (or --environment) was read whole (1 GiB sparse: 2.1 GB peak, 11-15
// s) before its header was looked at. The header is read first; the file is refused when it is larger than 16
// bytes a declared pixel plus 64 MiB, without reading it.
TEST(LoaderBounds, ImageFileIsNotReadPastWhatItsHeaderNeeds) {
    const test::TestDir dir("bounds");
    const std::string ppm = huge_ppm(dir);
    const uint64_t before = peak_rss();
    const std::string e = refusal([&] { Texture::load(ppm); });
    EXPECT_EQ(e, ppm + ": the file is 1073741824 bytes; a 2x2 image needs at most 67108928");
    const std::string gltf =
        dir.write("image.gltf", triangle_gltf(R"(, "images": [{"uri": "huge.ppm"}], "textures": [{"source": 0}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}])"));
    const Scene s = load_gltf(gltf);
    EXPECT_EQ(s.textures.size(), 0u);
    ASSERT_FALSE(s.warnings.empty());
    EXPECT_NE(s.warnings[0].find("a 2x2 image needs at most 67108928"), std::string::npos) << s.warnings[0];
    EXPECT_LT(peak_rss() - before, uint64_t(256) << 20);  // the file was not read (1 GiB)
    // The same file cut to its 27 bytes loads.
    std::filesystem::resize_file(ppm, 27);
    EXPECT_EQ(Texture::load(ppm).width(), 2);
}

// Issue 41 item 5: a buffer's file was read into a string, then copied into tinygltf's vector (2x its size at the
// peak); it is read straight into the vector. 256 MiB (sparse) buffer: the peak grows by about 256 MiB, not 512.
TEST(LoaderBounds, GltfBufferFileIsHeldOnce) {
    const test::TestDir dir("bounds");
    const uint64_t n = uint64_t(256) << 20;
    std::string tri(36, '\0');
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::memcpy(tri.data(), p, 36);
    std::filesystem::resize_file(dir.write("big.bin", tri), n);
    const std::string gltf =
        dir.write("big.gltf", R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 268435456, "uri": "big.bin"}]})");
    const uint64_t before = peak_rss();
    const Scene s = load_gltf(gltf);
    EXPECT_EQ(s.triangle_count(), 1u);
    const uint64_t grew = peak_rss() - before;
    EXPECT_LT(grew, n + n / 2) << grew / 1048576 << " MiB";
}

namespace {
// An 8-bit grey PNG of w x h zeros (one zlib stream: a few KB for millions of pixels).
std::string zero_png(uint32_t w, uint32_t h) {
    auto be32 = [](std::string& s, uint32_t v) {
        for (int i = 3; i >= 0; --i) s += char((v >> (8 * i)) & 0xff);
    };
    auto chunk = [&](std::string& png, const char* type, const std::string& data) {
        be32(png, uint32_t(data.size()));
        const std::string body = std::string(type, 4) + data;
        png += body;
        be32(png, uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
    };
    std::string png = "\x89PNG\r\n\x1a\n", ihdr;
    be32(ihdr, w);
    be32(ihdr, h);
    ihdr += std::string("\x08\x00\x00\x00\x00", 5);  // 8-bit grey, deflate, no filter, no interlace
    chunk(png, "IHDR", ihdr);
    const std::string raw(size_t(w + 1) * h, '\0');  // each row: filter byte 0, then w zeros
    uLongf n = compressBound(uLong(raw.size()));
    std::string z(n, '\0');
    compress2(reinterpret_cast<Bytef*>(z.data()), &n, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 9);
    z.resize(n);
    chunk(png, "IDAT", z);
    chunk(png, "IEND", "");
    return png;
}

std::string base64_of(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
        out += std::string{t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
    }
    if (i + 1 == in.size()) {
        const uint32_t v = uint32_t(uint8_t(in[i])) << 16;
        out += std::string{t[v >> 18], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
        const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8;
        out += std::string{t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
}
}  // namespace

// Issue 41 item 5: a 472 KB glTF with an embedded 11000x11000 PNG decoded to 1.4 GB (within the 135-MP budget of
// image files). Embedded images (data URI or bufferView) get max(2^24, 64 x their bytes) pixels: 4096x4096 of zeros
// (a few KB) is the most such a file decodes; one row more is refused in a warning, flat colour used.
TEST(LoaderBounds, EmbeddedGltfImageHasALowerDecodeBudget) {
    for (const uint32_t h : {4096u, 4097u}) {
        const std::string png = zero_png(4096, h);
        ASSERT_LT(uint64_t(png.size()) * 64, uint64_t(1) << 24);
        const Scene s =
            load_gltf_from_memory(triangle_gltf(R"(, "images": [{"uri": "data:image/png;base64,)" + base64_of(png) +
                                                R"("}], "textures": [{"source": 0}],
                "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}])"),
                                  "embedded.gltf");
        if (h == 4096) {
            EXPECT_EQ(s.textures.size(), 1u);
            for (const std::string& w : s.warnings) ADD_FAILURE() << w;
        } else {
            EXPECT_EQ(s.textures.size(), 0u);
            ASSERT_FALSE(s.warnings.empty());
            EXPECT_EQ(s.warnings[0].rfind("embedded.gltf: /images/0: an embedded 4096x4097 image in ", 0), 0u)
                << s.warnings[0];
            EXPECT_NE(s.warnings[0].find("over the budget of embedded images (16777216 pixels"), std::string::npos)
                << s.warnings[0];
        }
    }
}
}  // namespace pv
