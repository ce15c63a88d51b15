// tests/load/test_gltf_loader.cpp: the glTF loader (core/load/gltf_loader.h) on files the tests write (JSON with base64
// buffers, or .glb): transforms (nested, matrix and TRS, mirrored), accessor component types and strides, sparse
// accessors, strips and fans, cameras; damaged files end in one line naming the file and the JSON path, within
// little memory; and the Cornell box written as glTF renders the OBJ's image within noise, its .glb and .gltf forms
// bit for bit alike.
// Test kinds: unit; statistical: GltfCornellBox LightSamplingEmissiveTexture
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <thread>

#include "core/base/error.h"
#include "core/load/gltf_loader.h"
#include "core/load/obj_loader.h"
#include "core/load/scene_file.h"
#include "core/render/normal_map.h"
#include "core/scene/bsdf_pbr.h"
#include "tests/support/child.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125, kFloat = 5126;

std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
        for (int k = 3; k >= 0; --k) out += t[(v >> (6 * k)) & 63];
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

template <class T>
std::string bytes_of(std::initializer_list<T> values) {
    std::string s(values.size() * sizeof(T), '\0');
    std::memcpy(s.data(), values.begin(), s.size());
    return s;
}
template <class T>
std::string bytes_of(const std::vector<T>& values) {
    std::string s(values.size() * sizeof(T), '\0');
    std::memcpy(s.data(), values.data(), s.size());
    return s;
}

// A glTF document under construction: one buffer, written as a data: URI (text()), an external file, or the BIN
// chunk of a .glb (glb()).
struct Gltf {
    json j = {{"asset", {{"version", "2.0"}}}};
    std::string bin;

    int view(const std::string& bytes, int stride = 0) {
        while (bin.size() % 4) bin += '\0';
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}};
        if (stride) v["byteStride"] = stride;
        bin += bytes;
        j["bufferViews"].push_back(v);
        return int(j["bufferViews"].size() - 1);
    }
    int accessor(int view, int ctype, uint64_t count, const char* type, size_t offset = 0, bool normalized = false) {
        json a = {{"componentType", ctype}, {"count", count}, {"type", type}};
        if (view >= 0) a["bufferView"] = view;
        if (offset) a["byteOffset"] = offset;
        if (normalized) a["normalized"] = true;
        j["accessors"].push_back(a);
        return int(j["accessors"].size() - 1);
    }
    int floats(const std::vector<float>& v, const char* type, int ncomp) {
        return accessor(view(bytes_of(v)), kFloat, v.size() / size_t(ncomp), type);
    }
    // A mesh of one primitive; returns the mesh index.
    int mesh(json attributes, int indices = -1, int mode = -1, int material = -1) {
        json p = {{"attributes", attributes}};
        if (indices >= 0) p["indices"] = indices;
        if (mode >= 0) p["mode"] = mode;
        if (material >= 0) p["material"] = material;
        j["meshes"].push_back({{"primitives", json::array({p})}});
        return int(j["meshes"].size() - 1);
    }
    int node(json n) {
        j["nodes"].push_back(n);
        return int(j["nodes"].size() - 1);
    }
    void scene(json roots) {
        j["scenes"] = json::array({{{"nodes", roots}}});
        j["scene"] = 0;
    }
    // `declared`: the buffer's byteLength when not its true size (damaged files).
    std::string text(uint64_t declared = 0) const {
        json k = j;
        k["buffers"] = json::array({{{"byteLength", declared ? declared : bin.size()},
                                     {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
        return k.dump();
    }
    std::string text_with_bin(const std::string& bin_name, uint64_t declared = 0) const {
        json k = j;
        k["buffers"] = json::array({{{"byteLength", declared ? declared : bin.size()}, {"uri", bin_name}}});
        return k.dump();
    }
    std::string glb(uint64_t declared = 0) const {
        json k = j;
        k["buffers"] = json::array({{{"byteLength", declared ? declared : bin.size()}}});
        std::string js = k.dump();
        while (js.size() % 4) js += ' ';
        std::string b = bin;
        while (b.size() % 4) b += '\0';
        std::string out = "glTF";
        auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
        u32(2);
        u32(uint32_t(12 + 8 + js.size() + 8 + b.size()));
        u32(uint32_t(js.size()));
        u32(0x4E4F534Au);
        out += js;
        u32(uint32_t(b.size()));
        u32(0x004E4942u);
        out += b;
        return out;
    }
};

// The triangle (0,0,0), (1,0,0), (0,1,0) with +z normals, as mesh 0 of `g`.
int unit_triangle(Gltf& g) {
    const int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int nrm = g.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
    return g.mesh({{"POSITION", pos}, {"NORMAL", nrm}});
}

uint32_t le_json_length(const std::string& glb) {
    uint32_t n;
    std::memcpy(&n, glb.data() + 12, 4);
    return n;
}

Scene load(const std::string& bytes, const std::string& name = "test.gltf") {
    return load_gltf_from_memory(bytes, name);
}

vec3 geometric_normal(const Scene& s, size_t t) {
    const uvec3 i = s.triangles[t];
    return glm::normalize(glm::cross(s.positions[i.y] - s.positions[i.x], s.positions[i.z] - s.positions[i.x]));
}
vec3 shading_normal(const Scene& s, size_t t, int corner) { return s.normals[s.normal_indices[t][corner]]; }

// The triangle's corners, in its order, starting at the corner nearest `first` (rotations keep the winding).
std::vector<vec3> corners_from(const Scene& s, size_t t, vec3 first) {
    const uvec3 i = s.triangles[t];
    int k0 = 0;
    for (int k = 1; k < 3; ++k)
        if (glm::length(s.positions[i[k]] - first) < glm::length(s.positions[i[k0]] - first)) k0 = k;
    return {s.positions[i[k0]], s.positions[i[(k0 + 1) % 3]], s.positions[i[(k0 + 2) % 3]]};
}

void expect_near(vec3 a, vec3 b, float tol = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tol) << "(" << a.x << ", " << a.y << ", " << a.z << ")";
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

// ------------------------------------------------------------------------------------------------- geometry

TEST(GltfLoader, NestedTransformsMatrixAndTrsAndMirroredWinding) {
    Gltf g;
    const int tri = unit_triangle(g);
    // A tilted triangle whose normal a non-uniform scale turns: (0,0,0), (1,0,1), (0,1,0), normal ~ (-1, 0, 1).
    const float r = 1.f / std::sqrt(2.f);
    const int tilted_pos = g.floats({0, 0, 0, 1, 0, 1, 0, 1, 0}, "VEC3", 3);
    const int tilted_nrm = g.floats({-r, 0, r, -r, 0, r, -r, 0, r}, "VEC3", 3);
    const int tilted = g.mesh({{"POSITION", tilted_pos}, {"NORMAL", tilted_nrm}});
    const float s45 = std::sin(glm::radians(45.f)), c45 = std::cos(glm::radians(45.f));
    // root: translate (10,0,0) -> [ rotate 90 deg about z, scale 2 -> [ matrix: translate (0,0,5), mesh ] ],
    //                             [ scale (-1,1,1), mesh ]  (mirrored), [ scale (1,1,4), tilted mesh ]
    const int leaf = g.node({{"mesh", tri}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}}});
    const int mid = g.node({{"rotation", {0, 0, s45, c45}}, {"scale", {2, 2, 2}}, {"children", {leaf}}});
    const int mirrored = g.node({{"mesh", tri}, {"scale", {-1, 1, 1}}});
    const int stretched = g.node({{"mesh", tilted}, {"scale", {1, 1, 4}}});
    const int root = g.node({{"translation", {10, 0, 0}}, {"children", {mid, mirrored, stretched}}});
    g.scene({root});
    const Scene s = load(g.text());
    ASSERT_EQ(s.triangle_count(), 3u);
    // Depth-first order: the nested leaf, the mirrored instance, the stretched one.
    const auto a = corners_from(s, 0, vec3(10, 0, 10));
    expect_near(a[0], vec3(10, 0, 10));
    expect_near(a[1], vec3(10, 2, 10));
    expect_near(a[2], vec3(8, 0, 10));
    // The mirrored instance keeps its front face where its normal points: the winding is flipped.
    const auto b = corners_from(s, 1, vec3(10, 0, 0));
    expect_near(b[0], vec3(10, 0, 0));
    expect_near(b[1], vec3(10, 1, 0));
    expect_near(b[2], vec3(9, 0, 0));
    for (size_t t = 0; t < 3; ++t)
        for (int k = 0; k < 3; ++k) {
            // Shading normals by the inverse transpose agree with the transformed geometry's normal.
            EXPECT_GT(glm::dot(geometric_normal(s, t), shading_normal(s, t, k)), 0.99999f) << "triangle " << t;
        }
    expect_near(shading_normal(s, 2, 0), glm::normalize(vec3(-4, 0, 1)));
    EXPECT_FALSE(s.has_camera);
}

TEST(GltfLoader, AccessorComponentTypesNormalizedIntegersAndStrides) {
    Gltf g;
    // Interleaved: float position (12 bytes) + normalized ubyte uv (2 bytes) + 2 padding = stride 16.
    std::string inter;
    const float P[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const uint8_t UV[4][2] = {{0, 0}, {255, 0}, {255, 255}, {0, 51}};
    for (int i = 0; i < 4; ++i) {
        inter.append(reinterpret_cast<const char*>(P[i]), 12);
        inter.append(reinterpret_cast<const char*>(UV[i]), 2);
        inter.append(2, '\0');
    }
    const int iv = g.view(inter, 16);
    const int pos = g.accessor(iv, kFloat, 4, "VEC3");
    const int uv0 = g.accessor(iv, kUByte, 4, "VEC2", 12, true);
    // Normals: normalized bytes, 3 components padded to a stride of 4.
    const int nrm = g.accessor(g.view(bytes_of<int8_t>({0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0}), 4),
                               kByte, 4, "VEC3", 0, true);
    const int uv1 =
        g.accessor(g.view(bytes_of<uint16_t>({0, 0, 65535, 0, 65535, 65535, 0, 13107})), kUShort, 4, "VEC2", 0, true);
    const int idx = g.accessor(g.view(bytes_of<uint8_t>({0, 1, 2, 0, 2, 3})), kUByte, 6, "SCALAR");
    const int m0 = g.mesh({{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}}, idx);
    // Quantized positions (KHR_mesh_quantization): shorts by value, signed normalized shorts; 16- and 32-bit indices.
    const int qpos = g.accessor(g.view(bytes_of<int16_t>({100, 0, 0, 200, 0, 0, 100, 300, 0, 0})), kShort, 3, "VEC3");
    const int qidx = g.accessor(g.view(bytes_of<uint16_t>({0, 1, 2})), kUShort, 3, "SCALAR");
    const int m1 = g.mesh({{"POSITION", qpos}}, qidx);
    const int npos =
        g.accessor(g.view(bytes_of<int16_t>({-32768, 0, 0, 32767, 0, 0, 0, 16384, 0, 0})), kShort, 3, "VEC3", 0, true);
    const int uidx = g.accessor(g.view(bytes_of<uint32_t>({2, 1, 0})), kUInt, 3, "SCALAR");
    const int m2 = g.mesh({{"POSITION", npos}}, uidx);
    g.scene({g.node({{"mesh", m0}}), g.node({{"mesh", m1}}), g.node({{"mesh", m2}})});
    const Scene s = load(g.text());
    ASSERT_EQ(s.triangle_count(), 4u);
    // Quad: positions through the stride, uvs v-flipped into pathview's convention (v up).
    const uvec3 t1 = s.triangles[1];
    expect_near(s.positions[t1.x], vec3(0, 0, 0));
    expect_near(s.positions[t1.y], vec3(1, 1, 0));
    expect_near(s.positions[t1.z], vec3(0, 1, 0));
    ASSERT_EQ(s.uv_indices.size(), 4u);
    const uvec3 u1 = s.uv_indices[1];
    EXPECT_EQ(s.uvs[u1.y], vec2(1.f, 0.f));
    EXPECT_NEAR(s.uvs[u1.z].x, 0.f, 0.f);
    EXPECT_NEAR(s.uvs[u1.z].y, 1.f - 51.f / 255.f, 1e-6f);
    ASSERT_EQ(s.uv1_indices.size(), 4u);
    EXPECT_NEAR(s.uvs1[s.uv1_indices[1].z].y, 1.f - 0.2f, 1e-6f);
    EXPECT_EQ(s.normals[s.normal_indices[0].x], vec3(0, 0, 1));
    // Shorts by value; normalized shorts: max(c / 32767, -1).
    expect_near(s.positions[s.triangles[2].y], vec3(200, 0, 0));
    expect_near(s.positions[s.triangles[2].z], vec3(100, 300, 0));
    expect_near(s.positions[s.triangles[3].x], vec3(0, 16384.f / 32767.f, 0), 1e-6f);
    expect_near(s.positions[s.triangles[3].z], vec3(-1, 0, 0), 0.f);
    // Triangles of a primitive without normals or uvs have none.
    EXPECT_EQ(s.normal_indices[2].x, kNoIndex);
    EXPECT_EQ(s.uv_indices[3].x, kNoIndex);
}

TEST(GltfLoader, SparseAccessorsReplaceElements) {
    Gltf g;
    // A base of 3 vertices with vertex 2 replaced by (0, 1, 0); and one with no buffer view (zeros) and two
    // replaced.
    const int base = g.floats({0, 0, 0, 1, 0, 0, 7, 7, 7}, "VEC3", 3);
    g.j["accessors"][size_t(base)]["sparse"] = {
        {"count", 1},
        {"indices", {{"bufferView", g.view(bytes_of<uint16_t>({2}))}, {"componentType", kUShort}}},
        {"values", {{"bufferView", g.view(bytes_of<float>({0, 1, 0}))}}}};
    const int zeros = g.accessor(-1, kFloat, 3, "VEC3");
    g.j["accessors"][size_t(zeros)]["sparse"] = {
        {"count", 2},
        {"indices", {{"bufferView", g.view(bytes_of<uint8_t>({1, 2}))}, {"componentType", kUByte}}},
        {"values", {{"bufferView", g.view(bytes_of<float>({0, 0, 3, 0, 1, 3}))}}}};
    g.scene({g.node({{"mesh", g.mesh({{"POSITION", base}})}}), g.node({{"mesh", g.mesh({{"POSITION", zeros}})}})});
    const Scene s = load(g.text());
    ASSERT_EQ(s.triangle_count(), 2u);
    EXPECT_EQ(s.positions[s.triangles[0].z], vec3(0, 1, 0));
    EXPECT_EQ(s.positions[s.triangles[1].x], vec3(0, 0, 0));
    EXPECT_EQ(s.positions[s.triangles[1].y], vec3(0, 0, 3));
    EXPECT_EQ(s.positions[s.triangles[1].z], vec3(0, 1, 3));
}

TEST(GltfLoader, StripsAndFansAreTriangulatedPointsAndLinesSkippedWithOneWarning) {
    Gltf g;
    // A strip zig-zagging along x, every triangle facing -z when ordered as the specification says.
    const int strip = g.floats({0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0}, "VEC3", 3);
    // A fan about the origin, every triangle facing +z.
    const int fan = g.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0}, "VEC3", 3);
    const int m_strip = g.mesh({{"POSITION", strip}}, -1, 5);
    const int m_fan = g.mesh({{"POSITION", fan}}, -1, 6);
    const int m_lines = g.mesh({{"POSITION", fan}}, -1, 1);
    const int m_points = g.mesh({{"POSITION", fan}}, -1, 0);
    g.scene({g.node({{"mesh", m_strip}}), g.node({{"mesh", m_fan}}), g.node({{"mesh", m_lines}}),
             g.node({{"mesh", m_points}})});
    const Scene s = load(g.text());
    ASSERT_EQ(s.triangle_count(), 6u);
    for (size_t t = 0; t < 3; ++t) EXPECT_LT(geometric_normal(s, t).z, -0.999f) << "strip triangle " << t;
    for (size_t t = 3; t < 6; ++t) EXPECT_GT(geometric_normal(s, t).z, 0.999f) << "fan triangle " << t;
    size_t skipped = 0;
    for (const std::string& w : s.warnings) skipped += w.find("point or line") != std::string::npos;
    EXPECT_EQ(skipped, 1u);
}

TEST(GltfLoader, CamerasStartViewAndBookmarks) {
    Gltf g;
    const int tri = unit_triangle(g);
    g.j["cameras"] = {
        {{"name", "front"}, {"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}},
        {{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 9}}}},
        {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.1}}}}};
    const float s45 = std::sin(glm::radians(-45.f)), c45 = std::cos(glm::radians(-45.f));
    g.scene(
        {g.node({{"mesh", tri}}), g.node({{"camera", 1}, {"translation", {0, 0, 9}}}),
         g.node({{"camera", 0}, {"translation", {0, 0, 5}}}),
         g.node({{"name", "top view"}, {"camera", 2}, {"translation", {0, 10, 0}}, {"rotation", {s45, 0, 0, c45}}})});
    const Scene s = load(g.text());
    ASSERT_TRUE(s.has_camera);
    expect_near(s.camera.eye, vec3(0, 0, 5));
    EXPECT_NEAR(s.camera.vfov_deg, glm::degrees(0.5f), 1e-4f);
    const vec3 fwd = glm::normalize(s.camera.target - s.camera.eye);
    expect_near(fwd, vec3(0, 0, -1));
    ASSERT_EQ(s.bookmarks.size(), 2u);  // the orthographic camera is skipped (with a warning)
    EXPECT_EQ(s.bookmarks[0].name, "front");
    EXPECT_EQ(s.bookmarks[1].name, "top view");  // a camera without a name takes its node's
    expect_near(glm::normalize(s.bookmarks[1].camera.target - s.bookmarks[1].camera.eye), vec3(0, -1, 0));
    expect_near(s.bookmarks[1].camera.up, vec3(0, 0, -1));
    EXPECT_NEAR(s.bookmarks[1].camera.vfov_deg, glm::degrees(1.f), 1e-4f);
}

TEST(GltfLoader, UnsupportedExtensionsRequiredAreRefusedUsedOnesWarnedOnce) {
    Gltf g;
    g.scene({g.node({{"mesh", unit_triangle(g)}})});
    g.j["extensionsUsed"] = {"KHR_materials_iridescence", "KHR_materials_ior", "KHR_texture_basisu"};
    size_t warned = 0;
    const Scene s = load(g.text());
    for (const std::string& w : s.warnings) {
        warned += w.find("KHR_materials_iridescence") != std::string::npos;
        EXPECT_EQ(w.find("KHR_materials_ior"), std::string::npos) << w;
    }
    EXPECT_EQ(warned, 1u);
    g.j["extensionsRequired"] = {"KHR_materials_ior", "KHR_texture_basisu"};
    try {
        load(g.text(), "basisu.gltf");
        FAIL() << "a file requiring KTX2 textures loaded";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("basisu.gltf: /extensionsRequired/1: "), std::string::npos) << m;
        EXPECT_NE(m.find("'KHR_texture_basisu'"), std::string::npos) << m;
    }
}

// A 2x2 32-bit TGA (BGRA, top row first): Texture::decode tells formats by their bytes, so a glTF image may be one.
std::string tga_2x2(const uint8_t rgba[4][4]) {
    std::string t(18, '\0');
    t[2] = 2;                  // uncompressed true colour
    t[12] = 2, t[14] = 2;      // width, height
    t[16] = 32, t[17] = 0x28;  // 32 bits, 8 alpha bits, top-left origin
    for (int i = 0; i < 4; ++i)
        t += std::string{char(rgba[i][2]), char(rgba[i][1]), char(rgba[i][0]), char(rgba[i][3])};
    return t;
}

TEST(GltfLoader, MaterialsFactorsTexturesAlphaModesEmissionAndExtensions) {
    Gltf g;
    const uint8_t px[4][4] = {{255, 255, 255, 255}, {255, 0, 0, 100}, {0, 255, 0, 200}, {0, 0, 255, 0}};
    g.j["images"] = {{{"bufferView", g.view(tga_2x2(px))}, {"mimeType", "image/png"}}};
    g.j["textures"] = {{{"source", 0}}};
    const json transform = {{"KHR_texture_transform", {{"offset", {0.5, 0}}, {"scale", {2, 2}}}}};
    g.j["materials"] = {
        {{"name", "factor"},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {0.5, 1, 1, 1}}, {"baseColorTexture", {{"index", 0}, {"extensions", transform}}}}}},
        {{"name", "mask"},
         {"alphaMode", "MASK"},
         {"alphaCutoff", 0.5},
         {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}},
        {{"name", "lamp"},
         {"doubleSided", true},
         {"emissiveFactor", {1, 0.5, 0.25}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
        {{"name", "pbr"},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {0.2, 0.4, 0.6, 1}}, {"metallicFactor", 0.3}, {"roughnessFactor", 0.6}}},
         {"extensions",
          {{"KHR_materials_ior", {{"ior", 1.33}}},
           {"KHR_materials_specular", {{"specularFactor", 0.5}, {"specularColorFactor", {1, 0.5, 0.5}}}},
           {"KHR_materials_transmission", {{"transmissionFactor", 0.8}}},
           {"KHR_materials_volume",
            {{"thicknessFactor", 1}, {"attenuationColor", {0.9, 0.8, 0.7}}, {"attenuationDistance", 3}}}}}},
        {{"name", "blend"}, {"alphaMode", "BLEND"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.25}}}}}};
    const int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int uv = g.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
    json roots = json::array();
    for (int m = 0; m < 5; ++m)
        roots.push_back(g.node({{"mesh", g.mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, -1, m)}}));
    g.scene(roots);
    const Scene s = load(g.glb(), "materials.glb");
    ASSERT_EQ(s.materials.size(), 5u);
    for (const std::string& w : s.warnings) ADD_FAILURE() << w;
    // baseColorFactor x texture (sRGB decoded), baked; OPAQUE ignores the image's alpha.
    const Material& f = s.materials[0];
    ASSERT_NE(f.base_color_texture, kNoIndex);
    EXPECT_EQ(f.alpha_texture, kNoIndex);
    const std::vector<vec4> ft = s.textures[f.base_color_texture].texels();
    EXPECT_FLOAT_EQ(ft[0].x, 0.5f);
    EXPECT_FLOAT_EQ(ft[2].y, 1.f);
    // Its texture transform is applied to the triangle's uvs: (0.5, 0) + 2 uv, then v flipped (pathview's v up).
    const uvec3 ti = s.uv_indices[0];
    EXPECT_EQ(s.uvs[ti.x], vec2(0.5f, 1.f));
    EXPECT_EQ(s.uvs[ti.y], vec2(2.5f, 1.f));
    EXPECT_EQ(s.uvs[ti.z], vec2(0.5f, -1.f));
    // MASK: alpha cut at alphaCutoff into 0 or 1, the base colour texture doubling as the cut-out.
    const Material& m = s.materials[1];
    ASSERT_NE(m.alpha_texture, kNoIndex);
    EXPECT_EQ(m.alpha_texture, m.base_color_texture);
    const std::vector<vec4> mt = s.textures[m.alpha_texture].texels();
    EXPECT_EQ(mt[0].w, 1.f);
    EXPECT_EQ(mt[1].w, 0.f);  // 100 / 255 < 0.5
    EXPECT_EQ(mt[2].w, 1.f);  // 200 / 255 >= 0.5
    EXPECT_EQ(mt[3].w, 0.f);
    // emissiveFactor x KHR_materials_emissive_strength; doubleSided emits from both faces.
    EXPECT_EQ(s.materials[2].emission, vec3(4.f, 2.f, 1.f));
    EXPECT_TRUE(s.materials[2].two_sided_emission);
    EXPECT_FALSE(s.materials[0].two_sided_emission);
    // The metallic-roughness parameters and the KHR extensions.
    const auto* mr = std::get_if<MetallicRoughness>(&s.materials[3].bsdf);
    ASSERT_NE(mr, nullptr);
    EXPECT_NEAR(mr->base_color.y, 0.4f, 1e-6f);
    EXPECT_NEAR(mr->metallic, 0.3f, 1e-6f);
    EXPECT_NEAR(mr->roughness, 0.6f, 1e-6f);
    EXPECT_NEAR(mr->ior, 1.33f, 1e-6f);
    EXPECT_NEAR(mr->specular, 0.5f, 1e-6f);
    EXPECT_NEAR(mr->specular_color.y, 0.5f, 1e-6f);
    EXPECT_NEAR(mr->transmission, 0.8f, 1e-6f);
    EXPECT_FALSE(mr->thin_walled);
    EXPECT_NEAR(mr->attenuation_color.z, 0.7f, 1e-6f);
    EXPECT_NEAR(mr->attenuation_distance, 3.f, 1e-6f);
    // BLEND without a texture: a constant opacity as a 1x1 cut-out texture.
    ASSERT_NE(s.materials[4].alpha_texture, kNoIndex);
    EXPECT_EQ(s.textures[s.materials[4].alpha_texture].texels()[0].w, 0.25f);
}

// KHR_materials_clearcoat and KHR_materials_sheen: their factors, their textures (clearcoat's linear data undecoded,
// the sheen colour sRGB-decoded, the sheen roughness the alpha channel), the coat's normal map refused with a
// warning, a layer texture with its own transform refused with a warning (the factor used), and a zero factor leaves
// no layer at all.
TEST(GltfLoader, ClearcoatAndSheenFactorsAndTextures) {
    Gltf g;
    g.j["extensionsUsed"] = {"KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_texture_transform"};
    const uint8_t px[4][4] = {{255, 128, 64, 32}, {255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}};
    g.j["images"] = {{{"bufferView", g.view(tga_2x2(px))}, {"mimeType", "image/png"}}};
    g.j["textures"] = {{{"source", 0}}};
    const json moved = {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}};
    g.j["materials"] = {{{"name", "coated"},
                         {"extensions",
                          {{"KHR_materials_clearcoat",
                            {{"clearcoatFactor", 0.8},
                             {"clearcoatRoughnessFactor", 0.3},
                             {"clearcoatTexture", {{"index", 0}}},
                             {"clearcoatRoughnessTexture", {{"index", 0}}},
                             {"clearcoatNormalTexture", {{"index", 0}}}}}}}},
                        {{"name", "velvet"},
                         {"extensions",
                          {{"KHR_materials_sheen",
                            {{"sheenColorFactor", {1, 0.5, 0.25}},
                             {"sheenRoughnessFactor", 0.6},
                             {"sheenColorTexture", {{"index", 0}}},
                             {"sheenRoughnessTexture", {{"index", 0}, {"extensions", moved}}}}}}}},
                        {{"name", "none"},
                         {"extensions",
                          {{"KHR_materials_clearcoat", {{"clearcoatFactor", 0}, {"clearcoatTexture", {{"index", 0}}}}},
                           {"KHR_materials_sheen", {{"sheenRoughnessFactor", 0.5}}}}}}};
    const int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int uv = g.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
    json roots = json::array();
    for (int m = 0; m < 3; ++m)
        roots.push_back(g.node({{"mesh", g.mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, -1, m)}}));
    g.scene(roots);
    const Scene s = load(g.glb(), "layers.glb");
    ASSERT_EQ(s.materials.size(), 3u);
    const auto& coated = std::get<MetallicRoughness>(s.materials[0].bsdf);
    EXPECT_NEAR(coated.clearcoat, 0.8f, 1e-6f);
    EXPECT_NEAR(coated.clearcoat_roughness, 0.3f, 1e-6f);
    EXPECT_TRUE(coated.has(MetallicRoughness::kClearcoat));
    EXPECT_FALSE(coated.has(MetallicRoughness::kSheen));
    ASSERT_NE(s.materials[0].clearcoat_texture, kNoIndex);
    EXPECT_EQ(s.materials[0].clearcoat_roughness_texture, s.materials[0].clearcoat_texture) << "one linear copy";
    EXPECT_NEAR(s.textures[s.materials[0].clearcoat_texture].texels()[0].y, 128.f / 255.f, 1e-3f) << "undecoded";
    const auto& velvet = std::get<MetallicRoughness>(s.materials[1].bsdf);
    EXPECT_EQ(velvet.sheen_color, vec3(1.f, 0.5f, 0.25f));
    EXPECT_NEAR(velvet.sheen_roughness, 0.6f, 1e-6f);
    EXPECT_TRUE(velvet.has(MetallicRoughness::kSheen));
    ASSERT_NE(s.materials[1].sheen_color_texture, kNoIndex);
    EXPECT_NEAR(s.textures[s.materials[1].sheen_color_texture].texels()[0].y, srgb_code_to_linear(128), 1e-3f);
    EXPECT_EQ(s.materials[1].sheen_roughness_texture, kNoIndex) << "its own transform: the factor alone";
    const auto& none = std::get<MetallicRoughness>(s.materials[2].bsdf);
    EXPECT_FALSE(none.layered());
    EXPECT_FALSE(s.materials[2].has_layer_textures());
    ASSERT_EQ(s.warnings.size(), 2u);
    EXPECT_NE(s.warnings[0].find("/materials/0/extensions/KHR_materials_clearcoat/clearcoatNormalTexture"),
              std::string::npos)
        << s.warnings[0];
    EXPECT_NE(s.warnings[1].find("/materials/1/extensions/KHR_materials_sheen/sheenRoughnessTexture: a texture "
                                 "transform"),
              std::string::npos)
        << s.warnings[1];
}

// metallicRoughnessTexture: read as linear data (B metallic, G roughness), and a metallic factor of 1 with a texture
// keeps the diffuse and specular lobes a texel of metallic 0 needs: the material at a texel equals the untextured
// material of the texel's parameters.
TEST(GltfLoader, VertexColorsOfEveryAccessorTypeAreLoadedWhiteOnesNot) {
    Gltf g;
    const int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    // VEC4 normalized unsigned bytes (alpha not used), VEC3 normalized unsigned shorts, VEC3 floats, all-white floats.
    const int c8 = g.accessor(g.view(bytes_of<uint8_t>({255, 0, 0, 7, 0, 51, 0, 255, 0, 0, 255, 128})), kUByte, 3,
                              "VEC4", 0, true);
    const int c16 = g.accessor(g.view(bytes_of<uint16_t>({65535, 65535, 0, 0, 13107, 0, 0, 0, 65535})), kUShort, 3,
                               "VEC3", 0, true);
    const int cf = g.floats({0.25f, 0.5f, 0.75f, 1, 1, 1, 0, 0, 0}, "VEC3", 3);
    const int cw = g.floats({1, 1, 1, 1, 1, 1, 1, 1, 1}, "VEC3", 3);
    json nodes = json::array();
    for (int c : {c8, c16, cf, cw}) nodes.push_back(g.node({{"mesh", g.mesh({{"POSITION", pos}, {"COLOR_0", c}})}}));
    nodes.push_back(g.node({{"mesh", g.mesh({{"POSITION", pos}})}}));
    g.scene(nodes);
    const Scene s = load(g.text(), "colors.gltf");
    for (const std::string& w : s.warnings) ADD_FAILURE() << w;
    ASSERT_EQ(s.triangle_count(), 5u);
    ASSERT_EQ(s.color_indices.size(), 5u);
    auto corner = [&](size_t t, int k) { return s.colors[s.color_indices[t][k]]; };
    EXPECT_EQ(corner(0, 0), vec3(1, 0, 0));
    expect_near(corner(0, 1), vec3(0, 0.2f, 0), 1e-6f);
    EXPECT_EQ(corner(0, 2), vec3(0, 0, 1));
    EXPECT_EQ(corner(1, 0), vec3(1, 1, 0));
    expect_near(corner(1, 1), vec3(0, 0.2f, 0), 1e-6f);
    EXPECT_EQ(corner(2, 0), vec3(0.25f, 0.5f, 0.75f));
    EXPECT_EQ(corner(2, 2), vec3(0, 0, 0));
    // Interpolated at barycentrics (u, v) of corners 1 and 2.
    expect_near(s.color_at(2, 0.5f, 0.25f), 0.25f * vec3(0.25f, 0.5f, 0.75f) + 0.5f * vec3(1.f), 1e-6f);
    EXPECT_EQ(s.color_at(0, 0.f, 0.f), vec3(1, 0, 0));
    // All white, or no COLOR_0: nothing stored, nothing paid per hit.
    EXPECT_EQ(s.color_indices[3].x, kNoIndex);
    EXPECT_EQ(s.color_indices[4].x, kNoIndex);
    EXPECT_EQ(s.colors.size(), 9u);
    // A file whose colours are all white stores none at all, like an OBJ.
    Gltf white;
    const int wp = white.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int wc = white.floats({1, 1, 1, 1, 1, 1, 1, 1, 1}, "VEC3", 3);
    white.scene(json::array({white.node({{"mesh", white.mesh({{"POSITION", wp}, {"COLOR_0", wc}})}})}));
    const Scene sw = load(white.text(), "white.gltf");
    EXPECT_TRUE(sw.colors.empty());
    EXPECT_TRUE(sw.color_indices.empty());
}

TEST(GltfLoader, NormalTextureIsLinearWithItsScaleAndTangentsFromTheFile) {
    Gltf g;
    const uint8_t px[4][4] = {{128, 128, 255, 255}, {255, 128, 128, 255}, {128, 255, 128, 255}, {0, 128, 128, 255}};
    g.j["images"] = {{{"bufferView", g.view(tga_2x2(px))}, {"mimeType", "image/png"}}};
    g.j["textures"] = {{{"source", 0}}};
    g.j["materials"] = {{{"name", "bumpy"}, {"normalTexture", {{"index", 0}, {"scale", 0.5}}}},
                        {{"name", "bumpy elsewhere"}, {"normalTexture", {{"index", 0}, {"texCoord", 1}}}}};
    const int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int uv = g.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
    const int tan = g.floats({1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}, "VEC4", 4);
    const int m0 = g.mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}, {"TANGENT", tan}}, -1, -1, 0);
    // Mirrored in x: the tangent turns to -x and its handedness flips.
    g.scene(json::array({g.node({{"mesh", m0}}), g.node({{"mesh", m0}, {"scale", {-1, 1, 1}}}),
                         g.node({{"mesh", g.mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, -1, 1)}})}));
    const Scene s = load(g.text(), "normals.gltf");
    const Material& m = s.materials[0];
    ASSERT_NE(m.normal_texture, kNoIndex);
    EXPECT_EQ(m.normal_scale, 0.5f);
    const std::vector<vec4> t = s.textures[m.normal_texture].texels();
    EXPECT_NEAR(t[0].x, 128.f / 255.f, 1e-3f) << "the normal map is data, not sRGB colour";
    EXPECT_NEAR(t[0].z, 1.f, 1e-3f);
    // A texCoord other than the base colour's: not used, one warning naming it.
    EXPECT_EQ(s.materials[1].normal_texture, kNoIndex);
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_NE(s.warnings[0].find("/materials/1/normalTexture"), std::string::npos) << s.warnings[0];
    ASSERT_EQ(s.tangent_indices.size(), 3u);
    EXPECT_EQ(s.tangents[s.tangent_indices[0].x], vec4(1, 0, 0, 1));
    EXPECT_EQ(s.tangents[s.tangent_indices[1].x], vec4(-1, 0, 0, -1));
    EXPECT_EQ(s.tangent_indices[2].x, kNoIndex) << "no TANGENT: from the uvs at the hit";
}

// Samplers' wrapS / wrapT reach every texture the loader makes of an image: the base colour as it is and baked with
// its factor, the metallic-roughness, normal and emissive textures. One image under two samplers is two textures;
// no sampler, or a sampler without wrap modes, repeats; an invalid mode repeats with a warning naming it.
TEST(GltfLoader, SamplerWrapModesReachEveryTexture) {
    Gltf g;
    const uint8_t px[4][4] = {{255, 255, 255, 255}, {255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}};
    g.j["images"] = {{{"bufferView", g.view(tga_2x2(px))}, {"mimeType", "image/png"}}};
    g.j["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}},
                       {{"wrapS", 33648}, {"wrapT", 10497}},
                       {{"wrapT", 33071}},
                       json::object(),
                       {{"wrapS", 1234}}};
    g.j["textures"] = {{{"source", 0}, {"sampler", 0}},
                       {{"source", 0}, {"sampler", 1}},
                       {{"source", 0}, {"sampler", 2}},
                       {{"source", 0}, {"sampler", 3}},
                       {{"source", 0}},
                       {{"source", 0}, {"sampler", 4}}};
    g.j["materials"] = {
        {{"name", "clamp-mirror"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}},
        {{"name", "baked mirror-repeat"},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 1, 1, 1}}, {"baseColorTexture", {{"index", 1}}}}}},
        {{"name", "data"},
         {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 1}}}}},
         {"normalTexture", {{"index", 0}}},
         {"emissiveFactor", {1, 1, 1}},
         {"emissiveTexture", {{"index", 0}}}},
        {{"name", "repeat-clamp"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 2}}}}}},
        {{"name", "empty sampler"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 3}}}}}},
        {{"name", "no sampler"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 4}}}}}},
        {{"name", "invalid"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 5}}}}}}};
    const int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int uv = g.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
    json roots = json::array();
    for (int m = 0; m < 7; ++m)
        roots.push_back(g.node({{"mesh", g.mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, -1, m)}}));
    g.scene(roots);
    const Scene s = load(g.glb(), "wrap.glb");
    using W = TextureWrap;
    auto modes = [&](uint32_t t) {
        EXPECT_NE(t, kNoIndex);
        return t == kNoIndex ? std::pair{W::Repeat, W::Repeat}
                             : std::pair{s.textures[t].wrap_s(), s.textures[t].wrap_t()};
    };
    ASSERT_EQ(s.materials.size(), 7u);
    EXPECT_EQ(modes(s.materials[0].base_color_texture), std::pair(W::ClampToEdge, W::MirroredRepeat));
    EXPECT_EQ(modes(s.materials[1].base_color_texture), std::pair(W::MirroredRepeat, W::Repeat)) << "baked copy";
    EXPECT_EQ(modes(s.materials[2].metallic_roughness_texture), std::pair(W::MirroredRepeat, W::Repeat));
    EXPECT_EQ(modes(s.materials[2].normal_texture), std::pair(W::ClampToEdge, W::MirroredRepeat));
    EXPECT_EQ(modes(s.materials[2].emissive_texture), std::pair(W::ClampToEdge, W::MirroredRepeat));
    EXPECT_EQ(s.materials[2].emissive_texture, s.materials[0].base_color_texture) << "same image, same sampler";
    EXPECT_EQ(modes(s.materials[3].base_color_texture), std::pair(W::Repeat, W::ClampToEdge));
    EXPECT_EQ(modes(s.materials[4].base_color_texture), std::pair(W::Repeat, W::Repeat));
    EXPECT_EQ(modes(s.materials[5].base_color_texture), std::pair(W::Repeat, W::Repeat));
    EXPECT_EQ(modes(s.materials[6].base_color_texture), std::pair(W::Repeat, W::Repeat));
    // A lookup outside [0, 1] follows the mode: texel (0, 0) is white, (1, 0) red (row 0 on top, v up).
    const Texture& clamp_mirror = s.textures[s.materials[0].base_color_texture];
    EXPECT_EQ(clamp_mirror.lookup(vec2(-3.f, 0.75f)), vec4(1.f)) << "clamped to column 0";
    EXPECT_EQ(clamp_mirror.lookup(vec2(5.f, 0.75f)), vec4(1.f, 0.f, 0.f, 1.f)) << "clamped to column 1";
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_NE(s.warnings[0].find("/samplers/4/wrapS: wrap mode 1234"), std::string::npos) << s.warnings[0];
}

// The normal map's tangent space as the glTF specification defines it, from a file: red is +X, toward increasing u
// (the image's right); green is +Y, up the image, toward decreasing glTF v (glTF's v runs down the image: row 0 is
// v = 0); the TANGENT's w gives the bitangent w cross(N, T); the scale multiplies X and Y. A unit quad in the xy plane
// facing +z, its image upright (glTF v = 1 - y) or mirrored left to right (u = 1 - x), its tangent space from the
// uvs or from a TANGENT attribute: the shading normal normal_mapped gives (the integrator's) is the texel's
// normal in that frame, and a mirror about it reflects a ray as the closed form says.
TEST(GltfLoader, NormalMapTangentSpaceFollowsTheSpecificationsConvention) {
    const uint8_t code[3] = {160, 215, 230};  // x, y, z > 0: tilted right and up the image
    const uint8_t px[4][4] = {{code[0], code[1], code[2], 255},
                              {code[0], code[1], code[2], 255},
                              {code[0], code[1], code[2], 255},
                              {code[0], code[1], code[2], 255}};
    const vec3 t = 2.f * vec3(code[0], code[1], code[2]) / 255.f - 1.f;  // the texel's tangent-space normal
    struct Case {
        const char* name;
        bool mirrored_u;  // u = 1 - x: the image's right is -x
        int tangent_w;    // 0: no TANGENT (from the uvs); else TANGENT = (+-1, 0, 0, w) along increasing u
        float scale;
        vec3 right, up;  // the image's right and up on the quad, in world space (the spec's +X and +Y)
    };
    const Case cases[] = {
        {"upright, from uvs", false, 0, 1.f, vec3(1, 0, 0), vec3(0, 1, 0)},
        {"upright, TANGENT w = 1", false, 1, 1.f, vec3(1, 0, 0), vec3(0, 1, 0)},
        {"upright, scale 0.5", false, 0, 0.5f, vec3(1, 0, 0), vec3(0, 1, 0)},
        {"mirrored, from uvs", true, 0, 1.f, vec3(-1, 0, 0), vec3(0, 1, 0)},
        {"mirrored, TANGENT w = -1", true, -1, 1.f, vec3(-1, 0, 0), vec3(0, 1, 0)},
    };
    for (const Case& c : cases) {
        Gltf g;
        g.j["images"] = {{{"bufferView", g.view(tga_2x2(px))}, {"mimeType", "image/png"}}};
        g.j["textures"] = {{{"source", 0}}};
        g.j["materials"] = {{{"normalTexture", {{"index", 0}, {"scale", c.scale}}}}};
        const int pos = g.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3);
        const int nrm = g.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
        std::vector<float> uv;
        for (const vec2 p : {vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 1)}) {
            uv.push_back(c.mirrored_u ? 1.f - p.x : p.x);
            uv.push_back(1.f - p.y);  // glTF's v runs down the image: the image's top row is at y = 1
        }
        json attributes = {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", g.floats(uv, "VEC2", 2)}};
        if (c.tangent_w) {
            const float tx = c.mirrored_u ? -1.f : 1.f, w = float(c.tangent_w);
            attributes["TANGENT"] = g.floats({tx, 0, 0, w, tx, 0, 0, w, tx, 0, 0, w, tx, 0, 0, w}, "VEC4", 4);
        }
        const int idx = g.accessor(g.view(bytes_of<uint16_t>({0, 1, 2, 0, 2, 3})), kUShort, 6, "SCALAR");
        g.scene(json::array({g.node({{"mesh", g.mesh(attributes, idx, -1, 0)}})}));
        const Scene s = load(g.text(), "normal-convention.gltf");
        ASSERT_EQ(s.triangle_count(), 2u) << c.name;
        ASSERT_NE(s.materials[0].normal_texture, kNoIndex) << c.name;
        const Texture& map = s.textures[s.materials[0].normal_texture];
        // The specification: n = normalize(X right + Y up + Z N) with (X, Y, Z) = (2 texel - 1) (scale, scale, 1).
        const vec3 want = glm::normalize(c.scale * t.x * c.right + c.scale * t.y * c.up + t.z * vec3(0, 0, 1));
        for (uint32_t prim = 0; prim < 2; ++prim) {
            Hit hit;
            hit.prim = prim;
            hit.u = hit.v = 1.f / 3.f;
            const SurfacePoint sf = surface_point(s, hit);
            ASSERT_NEAR(sf.ng.z, 1.f, 1e-6f);
            const vec3 texel = vec3(map.lookup(s.uv_at(prim, hit.u, hit.v)));
            const vec3 n = normal_mapped(s, prim, hit.u, hit.v, sf, texel, s.materials[0].normal_scale);
            expect_near(n, want, 2e-3f);
            // A mirror about it: a ray coming straight down the z axis leaves along 2 (n . wo) n - wo.
            const vec3 wo(0, 0, 1), r = 2.f * glm::dot(n, wo) * n - wo;
            const vec3 closed_form = 2.f * want.z * want - wo;
            expect_near(r, closed_form, 4e-3f);
            EXPECT_GT(glm::dot(r, c.right), 0.f) << c.name << ": tilted toward the image's right (+X)";
            EXPECT_GT(glm::dot(r, c.up), 0.f) << c.name << ": tilted toward the image's top (+Y)";
        }
    }
}

TEST(GltfLoader, MetallicRoughnessTextureIsLinearAndKeepsTheLobesItsTexelsNeed) {
    Gltf g;
    const uint8_t px[4][4] = {{0, 128, 0, 255}, {0, 255, 255, 255}, {0, 64, 128, 255}, {0, 0, 255, 255}};
    g.j["images"] = {{{"bufferView", g.view(tga_2x2(px))}, {"mimeType", "image/png"}}};
    g.j["textures"] = {{{"source", 0}}};
    g.j["materials"] = {{{"name", "textured metal"},
                         {"pbrMetallicRoughness",
                          {{"baseColorFactor", {0.8, 0.5, 0.2, 1}},
                           {"metallicFactor", 1},
                           {"roughnessFactor", 1},
                           {"metallicRoughnessTexture", {{"index", 0}}}}}}};
    const int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int uv = g.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
    g.scene(json::array({g.node({{"mesh", g.mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, -1, 0)}})}));
    const Scene s = load(g.text(), "mr.gltf");
    for (const std::string& w : s.warnings) ADD_FAILURE() << w;
    const Material& m = s.materials[0];
    ASSERT_NE(m.metallic_roughness_texture, kNoIndex);
    const std::vector<vec4> t = s.textures[m.metallic_roughness_texture].texels();
    EXPECT_NEAR(t[0].y, 128.f / 255.f, 1e-3f) << "the texture is data, not sRGB colour";
    EXPECT_NEAR(t[2].z, 128.f / 255.f, 1e-3f);
    const auto* mr = std::get_if<MetallicRoughness>(&m.bsdf);
    ASSERT_NE(mr, nullptr);
    EXPECT_FALSE(is_delta(m.bsdf));
    for (const vec4& texel : t) {
        MetallicRoughness at = *mr;
        apply_metallic_roughness_texel(at, texel.z, texel.y);
        MetallicRoughness want;
        want.base_color = mr->base_color;
        want.metallic = texel.z;
        want.roughness = glm::max(texel.y, 0.f);
        prepare_metallic_roughness(want);
        if (want.alpha == 0.f) continue;  // a texel roughness of 0 stays rough (kMinAlpha): compared elsewhere
        for (const vec3 wo : {vec3(0.f, 0.f, 1.f), glm::normalize(vec3(0.5f, 0.1f, 0.7f))})
            for (const vec3 wi : {glm::normalize(vec3(-0.3f, 0.2f, 0.9f)), glm::normalize(vec3(0.6f, -0.5f, 0.3f))}) {
                const vec3 a = eval(Bsdf(at), wo, wi), b = eval(Bsdf(want), wo, wi);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(a[c], b[c], 1e-5f * (1.f + b[c])) << "texel " << texel.z << "," << texel.y;
                EXPECT_NEAR(pdf(Bsdf(at), wo, wi), pdf(Bsdf(want), wo, wi), 1e-4f);
            }
    }
}

// ------------------------------------------------------------------------------------------------- bad files

using test::ChildResult;
using test::run_bounded;

struct TempDir : test::TestDir {
    TempDir() : TestDir("pathview-gltf") {}
};

TEST(GltfLoader, DamagedFilesEndInOneLineNamingTheFileAndJsonPathWithinLittleMemory) {
    TempDir dir;
    auto good = [] {
        Gltf g;
        g.scene({g.node({{"mesh", unit_triangle(g)}})});
        return g;
    };
    struct Case {
        const char* what;
        std::string file;
        std::vector<std::string> expected;  // substrings of the message
    };
    std::vector<Case> cases;
    {
        Gltf g = good();
        cases.push_back({"missing .bin",
                         dir.write("missing.gltf", g.text_with_bin("missing.bin")),
                         {"/buffers/0/uri: 'missing.bin' not found"}});
    }
    {
        const std::string glb = good().glb();
        cases.push_back({"truncated .glb", dir.write("truncated.glb", glb.substr(0, glb.size() / 2)), {"truncated"}});
        cases.push_back({"wrong magic", dir.write("magic.glb", "glTX" + glb.substr(4)), {"magic 'glTF'", "'glTX'"}});
        std::string bad_bin = glb;  // the BIN chunk declaring 8 bytes more than the file holds
        const size_t bin_header = 20 + size_t(le_json_length(glb));
        uint32_t n;
        std::memcpy(&n, bad_bin.data() + bin_header, 4);
        n += 8;
        std::memcpy(bad_bin.data() + bin_header, &n, 4);
        cases.push_back({"BIN chunk past the end", dir.write("binchunk.glb", bad_bin), {"BIN chunk declares"}});
    }
    {
        Gltf g = good();
        g.j["accessors"][0]["count"] = 100;
        cases.push_back({"accessor past its buffer", dir.write("past.gltf", g.text()), {"/accessors/0: count 100"}});
        g.j["accessors"][0]["count"] = uint64_t(1) << 31;
        cases.push_back({"count 2^31", dir.write("count.gltf", g.text()), {"/accessors/0: count 2147483648"}});
        g.j["accessors"][0]["count"] = 3;
        g.j["bufferViews"][0]["byteLength"] = 4096;
        cases.push_back({"bufferView past its buffer", dir.write("view.gltf", g.text()), {"/bufferViews/0: "}});
    }
    {
        Gltf g = good();
        g.j["nodes"][0]["children"] = {1};
        g.j["nodes"].push_back({{"children", {0}}});
        cases.push_back({"node cycle", dir.write("cycle.gltf", g.text()), {"/nodes/1/children/0: ", "cycle"}});
    }
    {
        Gltf g = good();
        const uint64_t gb = uint64_t(1) << 30;
        cases.push_back({"1 GB declared in a data URI",
                         dir.write("huge.gltf", g.text(gb)),
                         {"/buffers/0/byteLength: declares 1073741824"}});
        cases.push_back({"1 GB declared in a .glb",
                         dir.write("huge.glb", g.glb(gb)),
                         {"/buffers/0/byteLength: declares 1073741824"}});
        dir.write("small.bin", g.bin);
        cases.push_back({"1 GB declared for a small .bin",
                         dir.write("huge-bin.gltf", g.text_with_bin("small.bin", gb)),
                         {"/buffers/0/byteLength: declares 1073741824", "has " + std::to_string(g.bin.size())}});
    }
    {
        Gltf g = good();
        g.j["meshes"][0]["primitives"][0]["indices"] =
            g.accessor(g.view(bytes_of<uint16_t>({0, 1, 3})), kUShort, 3, "SCALAR");
        cases.push_back({"index past the vertices",
                         dir.write("index.gltf", g.text()),
                         {"/meshes/0/primitives/0/indices: index 3"}});
        // The largest 32-bit index (a float rounds it to 2^32, whose cast to uint32_t was undefined: fuzz_gltf).
        g.j["meshes"][0]["primitives"][0]["indices"] =
            g.accessor(g.view(bytes_of<uint32_t>({0, 1, 4294967295u})), kUInt, 3, "SCALAR");
        cases.push_back({"index 2^32 - 1",
                         dir.write("index32.gltf", g.text()),
                         {"/meshes/0/primitives/0/indices: index 4294967295"}});
    }
    cases.push_back({"not JSON", dir.write("garbage.gltf", "{\"asset\": [1, 2"), {"invalid JSON"}});
    {
        // A mesh of 4096 vertices (48 kB) placed 2^15 times through nodes that name their child twice: 2^27
        // vertices (8 GB) from a 64 kB file.
        Gltf g;
        std::vector<float> pos(3 * 4096, 0.f);
        pos[3] = 1.f, pos[7] = 1.f;
        const int mesh = g.mesh({{"POSITION", g.floats(pos, "VEC3", 3)}},
                                g.accessor(g.view(bytes_of<uint16_t>({0, 1, 2})), kUShort, 3, "SCALAR"));
        for (int k = 0; k < 15; ++k) g.node({{"children", {k + 1, k + 1}}});
        g.node({{"mesh", mesh}});
        g.scene({0});
        cases.push_back(
            {"instancing bomb", dir.write("bomb.gltf", g.text()), {"/meshes/0/primitives/0: the scene would exceed"}});
        // 2^21 node visits of nothing.
        Gltf h;
        for (int k = 0; k < 21; ++k) h.node({{"children", {k + 1, k + 1}}});
        h.node(json::object());
        h.scene({0});
        h.view("abcd");
        cases.push_back({"node visits", dir.write("visits.gltf", h.text()), {"node instances"}});
    }

    const ChildResult idle = run_bounded([] { return 0; });
    ASSERT_TRUE(idle.finished);
    for (const Case& c : cases) {
        const ChildResult r = run_bounded([&] {
            try {
                load_scene(c.file);
            } catch (const Error& e) {
                const std::string m = e.what();
                if (m.find('\n') != std::string::npos) return 2;
                if (m.rfind(c.file + ": ", 0) != 0) return 3;
                for (const std::string& x : c.expected)
                    if (m.find(x) == std::string::npos) {
                        std::fprintf(stderr, "%s: message: %s\n", c.what, m.c_str());
                        return 4;
                    }
                return 0;
            }
            return 5;  // loaded
        });
        ASSERT_TRUE(r.finished) << c.what;
        EXPECT_EQ(r.exit_code, 0) << c.what << " (2: several lines, 3: no file name, 4: wrong text, 5: loaded)";
#if !defined(PATHVIEW_SANITIZED)
        // The memory bound holds for the allocator users run; ASan's shadow memory and quarantine inflate RSS by a
        // factor that says nothing about the loader (the sanitizer run checks the rest of this test).
        EXPECT_LT(r.max_rss_kb - idle.max_rss_kb, 64 * 1024) << c.what;
#endif
    }
}

TEST(GltfLoader, SceneFileNamesAGltfFileWithItsCameraOverridesAndBookmarks) {
    TempDir dir;
    Gltf g;
    const int tri = unit_triangle(g);
    g.j["cameras"] = {
        {{"name", "file view"}, {"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    g.scene({g.node({{"mesh", tri}}), g.node({{"camera", 0}, {"translation", {0, 0, 5}}})});
    dir.write("model.glb", g.glb());
    // Without "camera": the file's camera; with it, the JSON's; the file's cameras come before the JSON's bookmarks.
    const Scene a = load_scene(dir.write("a.json", R"({"obj": "model.glb", "background": [0.1, 0.1, 0.1]})"));
    expect_near(a.camera.eye, vec3(0, 0, 5));
    EXPECT_EQ(a.environment.background, vec3(0.1f));
    const Scene b = load_scene(dir.write(
        "b.json", R"({"obj": "model.glb", "camera": {"eye": [1, 2, 3]}, "bookmarks": [{"name": "mine", "fov": 30}]})"));
    expect_near(b.camera.eye, vec3(1, 2, 3));
    ASSERT_EQ(b.bookmarks.size(), 2u);
    EXPECT_EQ(b.bookmarks[0].name, "file view");
    EXPECT_EQ(b.bookmarks[1].name, "mine");
    // A bookmark saved for a .glb goes to "<file>.json", which loads the .glb again.
    const std::string saved = save_bookmark((dir.path / "model.glb").string(), "saved", b.camera);
    EXPECT_EQ(saved, (dir.path / "model.glb.json").string());
    const Scene c = load_scene(saved);
    EXPECT_EQ(c.triangle_count(), 1u);
    EXPECT_NO_THROW(find_bookmark(c, "saved"));
    EXPECT_NO_THROW(find_bookmark(c, "file view"));
}

TEST(GltfLoader, ExternalBinAndImageFilesWithPercentEncodedNames) {
    TempDir dir;
    Gltf g;
    const int tri = g.mesh({{"POSITION", g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3)},
                            {"TEXCOORD_0", g.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2)}},
                           -1, -1, 0);
    const uint8_t px[4][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 255, 255}};
    dir.write("my texture.tga", tga_2x2(px));
    g.j["images"] = {{{"uri", "my%20texture.tga"}}};
    g.j["textures"] = {{{"source", 0}}};
    g.j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    g.scene({g.node({{"mesh", tri}})});
    dir.write("my mesh.bin", g.bin);
    const Scene s = load_scene(dir.write("external.gltf", g.text_with_bin("my%20mesh.bin")));
    for (const std::string& w : s.warnings) EXPECT_NE(w.find("no emitter"), std::string::npos) << w;
    ASSERT_EQ(s.triangle_count(), 1u);
    ASSERT_NE(s.materials[0].base_color_texture, kNoIndex);
    EXPECT_EQ(s.textures[s.materials[0].base_color_texture].texels()[0], vec4(1, 0, 0, 1));
    // A missing image is a warning and the flat colour, not an error.
    fs::remove(dir.path / "my texture.tga");
    const Scene t = load_scene((dir.path / "external.gltf").string());
    EXPECT_EQ(t.materials[0].base_color_texture, kNoIndex);
    bool warned = false;
    for (const std::string& w : t.warnings)
        warned |= w.find("/pbrMetallicRoughness/baseColorTexture") != std::string::npos;
    EXPECT_TRUE(warned);
}

// ------------------------------------------------------------------------------------------------- Cornell box

// The OBJ Cornell box as glTF: one primitive per material (baseColorFactor = Kd, metallic 0, KHR_materials_specular
// factor 0: a pure Lambertian base), the light's Ke as emissiveFactor x KHR_materials_emissive_strength, and the
// scene file's camera as a camera node.
// `vertex_colors`: each material's colour is given as a uniform COLOR_0 on its primitive, over a white factor.
Gltf cornell_as_gltf(const Scene& obj, const CameraDesc& cam, bool vertex_colors = false) {
    Gltf g;
    g.j["extensionsUsed"] = {"KHR_materials_specular", "KHR_materials_emissive_strength"};
    std::vector<float> pos;
    for (const vec3& p : obj.positions) pos.insert(pos.end(), {p.x, p.y, p.z});
    const int pa = g.floats(pos, "VEC3", 3);
    json prims = json::array();
    for (size_t m = 0; m < obj.materials.size(); ++m) {
        std::vector<uint32_t> idx;
        for (size_t t = 0; t < obj.triangles.size(); ++t)
            if (obj.material_ids[t] == m)
                idx.insert(idx.end(), {obj.triangles[t].x, obj.triangles[t].y, obj.triangles[t].z});
        if (idx.empty()) continue;
        const int ia = g.accessor(g.view(bytes_of(idx)), kUInt, idx.size(), "SCALAR");
        const vec3 kd = std::get<Lambertian>(obj.materials[m].bsdf).albedo;
        json attributes = {{"POSITION", pa}};
        if (vertex_colors) {
            std::vector<float> col;
            for (size_t i = 0; i < obj.positions.size(); ++i) col.insert(col.end(), {kd.x, kd.y, kd.z});
            attributes["COLOR_0"] = g.floats(col, "VEC3", 3);
        }
        prims.push_back({{"attributes", attributes}, {"indices", ia}, {"material", m}});
        const vec3 factor = vertex_colors ? vec3(1.f) : kd;
        json mat = {{"name", obj.materials[m].name},
                    {"pbrMetallicRoughness",
                     {{"baseColorFactor", {factor.x, factor.y, factor.z, 1.0}}, {"metallicFactor", 0.0}}},
                    {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}};
        const vec3 ke = obj.materials[m].emission;
        if (max_component(ke) > 0.f) {
            const float strength = max_component(ke);
            mat["emissiveFactor"] = {ke.x / strength, ke.y / strength, ke.z / strength};
            mat["extensions"]["KHR_materials_emissive_strength"] = {{"emissiveStrength", strength}};
        }
        g.j["materials"].push_back(mat);
    }
    g.j["meshes"] = json::array({{{"primitives", prims}}});
    // The camera looks down its -z: from eye toward +z is a half turn about y.
    g.j["cameras"] = {
        {{"type", "perspective"}, {"perspective", {{"yfov", glm::radians(cam.vfov_deg)}, {"znear", 1.0}}}}};
    g.scene({g.node({{"mesh", 0}}),
             g.node({{"camera", 0}, {"translation", {cam.eye.x, cam.eye.y, cam.eye.z}}, {"rotation", {0, 1, 0, 0}}})});
    return g;
}

test::PixelStats stats_of(const Film& f) { return test::PixelStats::from_film(f); }

TEST(GltfCornellBox, RendersTheObjImageWithinNoiseAndGlbEqualsGltfBitForBit) {
    const std::string assets = fs::path(builtin_scene_path()).parent_path().string();
    const Scene obj_only = load_obj(assets + "/cornell-box.obj");
    auto obj = test::cornell_box();
    TempDir dir;
    const Gltf g = cornell_as_gltf(obj_only, obj->camera);
    const std::string gltf_path = dir.write("cornell.gltf", g.text());
    const std::string glb_path = dir.write("cornell.glb", g.glb());
    auto from_gltf = std::make_shared<Scene>(load_scene(gltf_path));
    auto from_glb = std::make_shared<Scene>(load_scene(glb_path));
    ASSERT_EQ(from_gltf->triangle_count(), obj->triangle_count());
    ASSERT_TRUE(from_gltf->has_camera);
    expect_near(from_gltf->camera.eye, obj->camera.eye, 1e-3f);
    expect_near(glm::normalize(from_gltf->camera.target - from_gltf->camera.eye),
                glm::normalize(obj->camera.target - obj->camera.eye));
    EXPECT_NEAR(from_gltf->camera.vfov_deg, obj->camera.vfov_deg, 1e-3f);

    RenderSettings rs;
    rs.sampler = SamplerKind::Independent;  // compare_images uses the i.i.d. sample variance
    const int w = 32, h = 32, spp = 256;
    rs.seed = 21;
    const Film f_obj = test::render_with_renderer(obj, obj->camera, rs, w, h, spp);
    rs.seed = 22;
    const Film f_gltf = test::render_with_renderer(from_gltf, from_gltf->camera, rs, w, h, spp);
    const Film f_glb = test::render_with_renderer(from_glb, from_glb->camera, rs, w, h, spp);
    const test::ImageComparison c = test::compare_images(stats_of(f_obj), stats_of(f_gltf));
    EXPECT_TRUE(c.passed) << c.describe();
    EXPECT_GT(stats_of(f_gltf).total_mean(), 0.01);
    // The same file content as .glb or .gltf: the same scene, the same image bit for bit.
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < 3; ++k) ASSERT_EQ(f_gltf.pixel(x, y).sum[k], f_glb.pixel(x, y).sum[k]) << x << "," << y;
}

// A uniform COLOR_0 of c over a white base colour renders the image of a base colour factor of c, bit for bit (the
// same seed: the colour interpolates to itself exactly and multiplies the factor 1).
TEST(GltfVertexColors, UniformColor0EqualsTheBaseColorFactorBitForBit) {
    const std::string assets = fs::path(builtin_scene_path()).parent_path().string();
    const Scene obj_only = load_obj(assets + "/cornell-box.obj");
    const CameraDesc cam = test::cornell_box()->camera;
    auto by_factor = std::make_shared<Scene>(load(cornell_as_gltf(obj_only, cam).text(), "factor.gltf"));
    auto by_color = std::make_shared<Scene>(load(cornell_as_gltf(obj_only, cam, true).text(), "color.gltf"));
    EXPECT_TRUE(by_factor->colors.empty());
    ASSERT_EQ(by_color->color_indices.size(), by_color->triangle_count());
    for (const std::string& w : by_color->warnings) EXPECT_EQ(w.find("COLOR_0"), std::string::npos) << w;
    RenderSettings rs;
    rs.seed = 5;
    const int w = 24, h = 24, spp = 16;
    const Film a = test::render_with_renderer(by_factor, by_factor->camera, rs, w, h, spp);
    const Film b = test::render_with_renderer(by_color, by_color->camera, rs, w, h, spp);
    EXPECT_GT(stats_of(a).total_mean(), 0.01);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < 3; ++k) ASSERT_EQ(a.pixel(x, y).sum[k], b.pixel(x, y).sum[k]) << x << "," << y;
}

// ------------------------------------------------------------------------------------------ emissive texture

// A w x 1 32-bit TGA (BGRA): Texture::decode tells formats by their bytes, so a glTF image may be one.
std::string tga_row(const std::vector<std::array<uint8_t, 4>>& rgba) {
    std::string t(18, '\0');
    t[2] = 2;                              // uncompressed true colour
    t[12] = char(rgba.size()), t[14] = 1;  // width, height
    t[16] = 32, t[17] = 0x28;              // 32 bits, 8 alpha bits, top-left origin
    for (const auto& p : rgba) t += std::string{char(p[2]), char(p[1]), char(p[0]), char(p[3])};
    return t;
}

// glTF's emissiveTexture: a lamp quad (x in [-1, 1], y in [-0.5, 0.5], z = 0, facing +z; emissiveFactor 1, black
// base) under a 2 x 1 texture, white then black along u = (x + 1) / 2, clamped at the edges (bilinear: white for
// u < 1/4, black for u > 3/4), and a grey floor at y = -1 in front of it. The camera sees emission 1 over the white
// texel and 0 over the black one (every sample: the lamp reflects nothing); at a floor point, NEE alone and NEE+MIS
// (power and tree selection) agree with BSDF sampling alone within a Sidak-corrected z bound from the sample variance.
// Before the fix the lamp shone 1 everywhere, seen and light-sampled.
TEST(LightSamplingEmissiveTexture, SeenAndLightSampledEmissionFollowTheTexture) {
    Gltf g;
    g.j["extensionsUsed"] = {"KHR_materials_specular"};
    g.j["images"] = {
        {{"bufferView", g.view(tga_row({{255, 255, 255, 255}, {0, 0, 0, 255}}))}, {"mimeType", "image/png"}}};
    g.j["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33071}}};
    g.j["textures"] = {{{"source", 0}, {"sampler", 0}}};
    const json lambert = {{"KHR_materials_specular", {{"specularFactor", 0.0}}}};
    g.j["materials"] = {{{"name", "lamp"},
                         {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}}},
                         {"extensions", lambert},
                         {"emissiveFactor", {1, 1, 1}},
                         {"emissiveTexture", {{"index", 0}}}},
                        {{"name", "floor"},
                         {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0.0}}},
                         {"extensions", lambert}}};
    const int idx = g.accessor(g.view(bytes_of<uint16_t>({0, 1, 2, 0, 2, 3})), kUShort, 6, "SCALAR");
    const int lamp_pos = g.floats({-1, -0.5, 0, 1, -0.5, 0, 1, 0.5, 0, -1, 0.5, 0}, "VEC3", 3);
    const int lamp_uv = g.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 2);
    const int floor_pos = g.floats({-2, -1, 3, 2, -1, 3, 2, -1, 0, -2, -1, 0}, "VEC3", 3);
    g.scene({g.node({{"mesh", g.mesh({{"POSITION", lamp_pos}, {"TEXCOORD_0", lamp_uv}}, idx, -1, 0)}}),
             g.node({{"mesh", g.mesh({{"POSITION", floor_pos}}, idx, -1, 1)}})});
    auto scene = std::make_shared<Scene>(load(g.text(), "emissive.gltf"));
    for (const std::string& w : scene->warnings) ADD_FAILURE() << w;
    ASSERT_EQ(scene->materials.size(), 2u);
    ASSERT_NE(scene->materials[0].emissive_texture, kNoIndex);
    ASSERT_EQ(scene->triangle_count(), 4u);
    test::Tracer tracer(scene);

    // Seen: a 32 x 32 view of x, y in [-0.8, 0.8] (vfov 2 atan(0.8 / 3)); columns 0-4 lie over u < 0.225, columns
    // 27-31 over u > 0.77, rows 10-21 within |y| < 0.3.
    CameraDesc cam;
    cam.eye = vec3(0.f, 0.f, 3.f);
    cam.target = vec3(0.f);
    cam.vfov_deg = float(glm::degrees(2.0 * std::atan(0.8 / 3.0)));
    RenderSettings rs;
    rs.sampler = SamplerKind::Independent;
    rs.seed = 3;
    int white = 0, black = 0, wrong = 0;
    std::string first_wrong;
    tracer.for_each_sample(cam, rs, 32, 32, 4, [&](int x, int y, uint32_t, vec3 v) {
        if (y < 10 || y > 21 || (x > 4 && x < 27)) return;
        const vec3 expected(x <= 4 ? 1.f : 0.f);
        ++(x <= 4 ? white : black);
        if (glm::any(glm::greaterThan(glm::abs(v - expected), vec3(1e-6f)))) {
            if (!wrong++)
                first_wrong = std::to_string(x) + "," + std::to_string(y) + ": " + std::to_string(v.x) + " expected " +
                              std::to_string(expected.x);
        }
    });
    EXPECT_EQ(wrong, 0) << "first: pixel " << first_wrong;
    EXPECT_EQ(white, 5 * 12 * 4);
    EXPECT_EQ(black, 5 * 12 * 4);

    // Light-sampled: the floor point (-0.3, -1, 1), seen through one pixel centre from above.
    CameraDesc cell;
    cell.eye = vec3(-0.3f, 0.5f, 2.f);
    cell.target = vec3(-0.3f, -1.f, 1.f);
    cell.vfov_deg = 1.f;
    struct Estimator {
        const char* name;
        bool nee, mis;
        LightSamplerKind light_sampler = LightSamplerKind::Power;
    };
    const Estimator estimators[] = {{"bsdf", false, false},
                                    {"nee", true, false},
                                    {"nee+mis", true, true},
                                    {"nee+mis/tree", true, true, LightSamplerKind::Tree}};
    constexpr int kEstimators = int(std::size(estimators));
    double mean[kEstimators], se[kEstimators];
    for (int e = 0; e < kEstimators; ++e) {
        RenderSettings s;
        s.sampler = SamplerKind::Independent;
        s.light_sampling = estimators[e].nee;
        s.mis = estimators[e].mis;
        s.light_sampler = estimators[e].light_sampler;
        tracer.set_light_sampler(estimators[e].light_sampler);  // as the Renderer applies it
        s.seed = 40 + uint32_t(e);
        test::Moments m;
        tracer.for_each_sample(
            cell, s, 1, 1, 40000, [&](int, int, uint32_t, vec3 v) { m.add(double(v.y)); }, /*pixel_centre=*/true);
        mean[e] = m.mean;
        se[e] = m.stderr_of_mean();
    }
    ASSERT_GT(mean[0], 0.0);
    const double k = test::sidak_k(double(kEstimators - 1));
    for (int e = 1; e < kEstimators; ++e) {
        const double z = (mean[e] - mean[0]) / std::hypot(se[e], se[0]);
        EXPECT_LE(std::fabs(z), k) << estimators[e].name << " " << mean[e] << " +- " << se[e] << " vs BSDF-only "
                                   << mean[0] << " +- " << se[0];
    }
}

}  // namespace
}  // namespace pv
