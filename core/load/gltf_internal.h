// core/load/gltf_internal.h: the glTF loader's shared parts (core/load/gltf_loader.cpp: files, parsing;
// core/load/gltf_meshes.cpp: nodes, meshes, lights; core/load/gltf_materials.cpp: materials, textures, cameras), with
// the bounds-checked accessors. Private to those three files: it includes tinygltf, which no public header of core/
// may.
#pragma once

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "core/base/error.h"
#include "core/scene/scene.h"

namespace pv::gltf_detail {

using glm::dmat3;
using glm::dmat4;
using glm::dvec4;

// What pathview reads: a file may require these (KHR_mesh_quantization only widens the accessor types allowed,
// which the loader reads in every case; the two compressions are decoded by core/load/gltf_compression.cpp). Anything
// else required is refused; anything else used is warned about.
inline constexpr const char* kSupportedExtensions[] = {
    "KHR_materials_emissive_strength",
    "KHR_texture_transform",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_lights_punctual",
    "KHR_mesh_quantization",
    "KHR_draco_mesh_compression",
    "EXT_meshopt_compression",
    "EXT_texture_webp",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
};

// tinygltf takes a file's size as a 32-bit unsigned int and copies every buffer once more: 2 GiB of file at most.
inline constexpr uint64_t kMaxGltfBytes = uint64_t(2) << 30;
// Node instances visited and triangles produced: a node hierarchy is a tree, but a file may reference a node twice
// and so instance a mesh exponentially often; these bound the work and the memory.
inline constexpr size_t kMaxNodeVisits = size_t(1) << 20;
inline constexpr size_t kMaxTriangles = size_t(1) << 27;
// What instancing may make of a file's bytes: a file may place a mesh many times, but a small file that would expand
// into gigabytes is refused. Vertices and triangles (each of them, counted with every instance) up to 2^22 or 16 per
// byte of the file's buffers, whichever is larger (each costs about 60 bytes in the scene).
inline constexpr size_t kMinInstancingBudget = size_t(1) << 22;
inline constexpr uint64_t kInstancingPerByte = 16;
inline constexpr float kMaxCoordinate = 1.844e18f;  // Embree ignores primitives beyond this (as obj_loader.cpp)

inline std::string ptr(std::initializer_list<std::string> parts) {
    std::string s;
    for (const std::string& p : parts) s += "/" + p;
    return s;
}
inline std::string str(size_t i) { return std::to_string(i); }

inline bool supported_extension(const std::string& name) {
    for (const char* e : kSupportedExtensions)
        if (name == e) return true;
    return false;
}

// A number from a tinygltf extension object (absent or not a number: `fallback`).
inline double value_number(const tinygltf::Value& o, const char* key, double fallback) {
    if (!o.IsObject() || !o.Has(key)) return fallback;
    const tinygltf::Value& v = o.Get(key);
    return v.IsNumber() || v.IsInt() ? v.GetNumberAsDouble() : fallback;
}
inline bool value_numbers(const tinygltf::Value& o, const char* key, double* out, int n) {
    if (!o.IsObject() || !o.Has(key)) return false;
    const tinygltf::Value& v = o.Get(key);
    if (!v.IsArray() || int(v.ArrayLen()) != n) return false;
    for (int i = 0; i < n; ++i) {
        const tinygltf::Value& e = v.Get(i);
        if (!e.IsNumber() && !e.IsInt()) return false;
        out[i] = e.GetNumberAsDouble();
    }
    return true;
}
inline const tinygltf::Value* extension(const tinygltf::ExtensionMap& m, const char* name) {
    const auto it = m.find(name);
    return it == m.end() || !it->second.IsObject() ? nullptr : &it->second;
}

inline float finite_or(double v, float fallback) { return std::isfinite(v) ? float(v) : fallback; }

struct Loader {
    Loader(std::string f, Scene& s) : file(std::move(f)), warnings(s.warnings), scene(&s) {}
    std::string file;
    std::vector<std::string>& warnings;
    tinygltf::Model model;
    std::map<int, Texture> images;  // decoded images by glTF image index (absent: not decodable)
    Scene* scene = nullptr;

    // Per glTF material: how the base colour texture reads its uvs (its texCoord and transform, baked into the
    // triangles' set-0 uvs; pathview's base colour and alpha lookups read set 0 untransformed).
    std::vector<UvTransform> base_uv;
    uint32_t default_material = kNoIndex;
    // (glTF image, wrap s, wrap t) -> Scene::textures index (as decoded, with the sampler's wrap modes)
    std::map<std::tuple<int, TextureWrap, TextureWrap>, uint32_t> image_texture;
    std::set<std::string> warned;  // one warning per kind

    size_t budget = kMinInstancingBudget;  // vertices and triangles at most (set from the buffers' size)
    size_t skipped_points_lines = 0, dropped_nonfinite = 0, dropped_degenerate = 0, visits = 0;

    void warn_once(const std::string& key, const std::string& text) {
        if (warned.insert(key).second) warnings.push_back(file + ": " + text);
    }
    [[noreturn]] void fail(const std::string& at, const std::string& what) const {
        throw Error(file + ": " + at + ": " + what);
    }

    // ---- Accessors ----

    static int component_bytes(int type) {
        switch (type) {
            case TINYGLTF_COMPONENT_TYPE_BYTE:
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                return 1;
            case TINYGLTF_COMPONENT_TYPE_SHORT:
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
                return 2;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            case TINYGLTF_COMPONENT_TYPE_FLOAT:
                return 4;
            default:
                return 0;
        }
    }
    static int type_components(int type) {
        switch (type) {
            case TINYGLTF_TYPE_SCALAR:
                return 1;
            case TINYGLTF_TYPE_VEC2:
                return 2;
            case TINYGLTF_TYPE_VEC3:
                return 3;
            case TINYGLTF_TYPE_VEC4:
                return 4;
            default:
                return 0;
        }
    }
    // One component as a float: normalized integers as the specification maps them (signed: max(c / (2^(b-1) - 1),
    // -1); unsigned: c / (2^b - 1)), other integers by value.
    static float component(const uint8_t* p, int type, bool normalized) {
        switch (type) {
            case TINYGLTF_COMPONENT_TYPE_BYTE: {
                int8_t v;
                std::memcpy(&v, p, 1);
                return normalized ? std::max(float(v) / 127.f, -1.f) : float(v);
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                return normalized ? float(*p) / 255.f : float(*p);
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                int16_t v;
                std::memcpy(&v, p, 2);
                return normalized ? std::max(float(v) / 32767.f, -1.f) : float(v);
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t v;
                std::memcpy(&v, p, 2);
                return normalized ? float(v) / 65535.f : float(v);
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
                uint32_t v;
                std::memcpy(&v, p, 4);
                return normalized ? float(double(v) / 4294967295.0) : float(v);
            }
            default: {
                float v;
                std::memcpy(&v, p, 4);
                return v;
            }
        }
    }

    // The bytes of `count` elements of `elem` bytes, `stride` apart, from byte `offset` of buffer view `view`,
    // every byte checked to lie inside the view and the view inside its buffer. `at` is the referring JSON path.
    const uint8_t* view_bytes(int view, uint64_t offset, uint64_t stride, uint64_t count, uint64_t elem,
                              const std::string& at) const {
        if (view < 0 || size_t(view) >= model.bufferViews.size())
            fail(at, "bufferView " + std::to_string(view) + " does not exist; the file has " +
                         str(model.bufferViews.size()));
        const tinygltf::BufferView& bv = model.bufferViews[size_t(view)];
        const std::string bv_at = ptr({"bufferViews", str(size_t(view))});
        if (bv.buffer < 0 || size_t(bv.buffer) >= model.buffers.size())
            fail(bv_at + "/buffer", "buffer " + std::to_string(bv.buffer) + " does not exist");
        const uint64_t buffer_size = model.buffers[size_t(bv.buffer)].data.size();
        if (bv.byteOffset > buffer_size || bv.byteLength > buffer_size - bv.byteOffset)
            fail(bv_at, "bytes " + str(bv.byteOffset) + " + " + str(bv.byteLength) + " lie past the end of buffer " +
                            std::to_string(bv.buffer) + ", which has " + str(buffer_size));
        if (count == 0) return nullptr;
        // stride <= 2^8 and count < 2^55 keep the products below in 64 bits.
        if (count > (uint64_t(1) << 55) / std::max<uint64_t>(stride, 1) || offset > bv.byteLength ||
            stride * (count - 1) + elem > bv.byteLength - offset)
            fail(at, "count " + str(count) + " of " + str(elem) + "-byte elements (stride " + str(stride) +
                         ") from byte " + str(offset) + " reads past the end of bufferView " + std::to_string(view) +
                         ", which has " + str(bv.byteLength) + " bytes");
        return model.buffers[size_t(bv.buffer)].data.data() + bv.byteOffset + offset;
    }

    // The accessor's elements as floats, `components` per element (sparse substitution applied). `types` lists
    // the accessor types allowed (TINYGLTF_TYPE_*); `at` is the JSON path of the reference.
    std::vector<float> read_floats(int index, const std::string& at, std::initializer_list<int> types,
                                   int& components) const {
        if (index < 0 || size_t(index) >= model.accessors.size())
            fail(at,
                 "accessor " + std::to_string(index) + " does not exist; the file has " + str(model.accessors.size()));
        const tinygltf::Accessor& a = model.accessors[size_t(index)];
        const std::string a_at = ptr({"accessors", str(size_t(index))});
        if (std::find(types.begin(), types.end(), a.type) == types.end())
            fail(a_at + "/type", "accessor type " + std::to_string(a.type) + " is not one this attribute takes");
        const int cb = component_bytes(a.componentType);
        if (!cb) fail(a_at + "/componentType", "component type " + std::to_string(a.componentType) + " is not valid");
        components = type_components(a.type);
        const uint64_t elem = uint64_t(cb) * uint64_t(components);
        std::vector<float> out;
        if (a.bufferView >= 0) {
            uint64_t stride = elem;
            if (size_t(a.bufferView) < model.bufferViews.size()) {
                const int s = model.bufferViews[size_t(a.bufferView)].byteStride;
                if (s != 0 && (s < 4 || s > 252 || uint64_t(s) < elem))
                    fail(ptr({"bufferViews", str(size_t(a.bufferView)), "byteStride"}),
                         "byteStride " + std::to_string(s) + " for " + str(elem) +
                             "-byte elements; expected 0 or 4..252 and at least the element size");
                if (s) stride = uint64_t(s);
            }
            const uint8_t* p = view_bytes(a.bufferView, a.byteOffset, stride, a.count, elem, a_at);
            out.resize(size_t(a.count) * size_t(components));
            for (size_t i = 0; i < a.count; ++i)
                for (int c = 0; c < components; ++c)
                    out[i * size_t(components) + size_t(c)] =
                        component(p + i * stride + size_t(c * cb), a.componentType, a.normalized);
        } else {
            // No buffer view: zeros (then the sparse values). The count is bounded by what the buffers could fill,
            // so that a small file cannot ask for a large allocation.
            uint64_t total = 0;
            for (const auto& b : model.buffers) total += b.data.size();
            if (a.count > total + 65536)
                fail(a_at + "/count", "count " + str(a.count) + " without a bufferView exceeds the file's " +
                                          str(total) + " bytes of buffers");
            out.assign(size_t(a.count) * size_t(components), 0.f);
        }
        if (a.sparse.isSparse) {
            const auto& sp = a.sparse;
            const std::string s_at = a_at + "/sparse";
            if (sp.count <= 0 || uint64_t(sp.count) > a.count)
                fail(s_at + "/count", "sparse count " + std::to_string(sp.count) + "; expected 1.." + str(a.count));
            const int icb = component_bytes(sp.indices.componentType);
            if (sp.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                sp.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                sp.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
                fail(s_at + "/indices/componentType", "expected an unsigned byte, short or int");
            if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0) fail(s_at, "negative byteOffset");
            const uint8_t* ip = view_bytes(sp.indices.bufferView, uint64_t(sp.indices.byteOffset), uint64_t(icb),
                                           uint64_t(sp.count), uint64_t(icb), s_at + "/indices");
            const uint8_t* vp = view_bytes(sp.values.bufferView, uint64_t(sp.values.byteOffset), elem,
                                           uint64_t(sp.count), elem, s_at + "/values");
            for (size_t k = 0; k < size_t(sp.count); ++k) {
                const float fi = component(ip + k * size_t(icb), sp.indices.componentType, false);
                const uint64_t i = uint64_t(fi);
                if (i >= a.count)
                    fail(s_at + "/indices", "index " + str(i) + " is past the accessor's count " + str(a.count));
                for (int c = 0; c < components; ++c)
                    out[i * size_t(components) + size_t(c)] =
                        component(vp + k * elem + size_t(c * cb), a.componentType, a.normalized);
            }
        }
        return out;
    }

    // Index accessor: unsigned byte, short or int scalars, each below `vertex_count`.
    std::vector<uint32_t> read_indices(int index, const std::string& at, size_t vertex_count) const {
        if (index >= 0 && size_t(index) < model.accessors.size()) {
            const int t = model.accessors[size_t(index)].componentType;
            if (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
                fail(ptr({"accessors", str(size_t(index)), "componentType"}),
                     "indices must be unsigned bytes, shorts or ints");
        }
        int comps = 0;
        const std::vector<float> f = read_floats(index, at, {TINYGLTF_TYPE_SCALAR}, comps);
        std::vector<uint32_t> out(f.size());
        for (size_t i = 0; i < f.size(); ++i) {
            // Indices above 2^24 are not exact in float (2^32 - 1 rounds to 2^32, outside uint32_t): read them
            // again exactly below, or refused as out of range.
            out[i] = f[i] < 4294967296.f ? uint32_t(f[i]) : UINT32_MAX;
        }
        // Re-read 32-bit indices exactly (float holds integers up to 2^24 only).
        const tinygltf::Accessor& a = model.accessors[size_t(index)];
        if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && a.bufferView >= 0 && !a.sparse.isSparse) {
            const tinygltf::BufferView& bv = model.bufferViews[size_t(a.bufferView)];
            const size_t stride = bv.byteStride ? size_t(bv.byteStride) : 4;
            const uint8_t* p = view_bytes(a.bufferView, a.byteOffset, stride, a.count, 4, at);
            for (size_t i = 0; i < out.size(); ++i) std::memcpy(&out[i], p + i * stride, 4);
        } else if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && vertex_count > (size_t(1) << 24)) {
            fail(ptr({"accessors", str(size_t(index))}), "sparse 32-bit indices into more than 2^24 vertices");
        }
        for (size_t i = 0; i < out.size(); ++i)
            if (out[i] >= vertex_count)
                fail(at, "index " + str(out[i]) + " at position " + str(i) + " is past the primitive's " +
                             str(vertex_count) + " vertices");
        return out;
    }

    // ---- Nodes ----

    dmat4 local_transform(const tinygltf::Node& n, size_t index) const {
        const std::string at = ptr({"nodes", str(index)});
        dmat4 m(1.0);
        if (!n.matrix.empty()) {
            if (n.matrix.size() != 16) fail(at + "/matrix", "expected 16 numbers");
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[size_t(c * 4 + r)];
        } else {
            dvec3 t(0.0), s(1.0);
            glm::dquat q(1.0, 0.0, 0.0, 0.0);
            if (!n.translation.empty()) {
                if (n.translation.size() != 3) fail(at + "/translation", "expected 3 numbers");
                t = dvec3(n.translation[0], n.translation[1], n.translation[2]);
            }
            if (!n.rotation.empty()) {
                if (n.rotation.size() != 4) fail(at + "/rotation", "expected 4 numbers (a quaternion x, y, z, w)");
                q = glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
                const double len = glm::length(q);
                if (!(len > 0.0) || !std::isfinite(len)) fail(at + "/rotation", "expected a non-zero quaternion");
                q = q / len;
            }
            if (!n.scale.empty()) {
                if (n.scale.size() != 3) fail(at + "/scale", "expected 3 numbers");
                s = dvec3(n.scale[0], n.scale[1], n.scale[2]);
            }
            m = glm::translate(dmat4(1.0), t) * glm::mat4_cast(q) * glm::scale(dmat4(1.0), s);
        }
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(m[c][r])) fail(at, "the transform is not finite");
        return m;
    }

    struct CameraInstance {
        int camera;
        int node;
        dmat4 world;
    };
    std::vector<CameraInstance> cameras;

    void add_mesh(int mesh_index, const dmat4& world, const std::string& at);
    void add_light(int light, const dmat4& world, const std::string& at);
    void traverse(int scene_index);

    // ---- Materials ----
    uint32_t image_texture_index(int image, TextureWrap s, TextureWrap t);
    TextureWrap wrap_mode(int gl, const std::string& at);
    uint32_t texture_of(const tinygltf::TextureInfo& info, const std::string& at, UvTransform& uv);
    void convert_materials();
    uint32_t material_index(int gltf_material, const std::string& at);
    void convert_cameras();
    void check_extensions();
};

}  // namespace pv::gltf_detail
