// core/gltf_loader.cpp: glTF 2.0 through tinygltf (see gltf_loader.h). A pre-pass over the JSON checks what
// tinygltf would read unchecked or report without a JSON path (required extensions, the buffers' sources and
// sizes, a .glb's chunk layout); tinygltf then parses, with pathview's own file reading and image decoding; the
// conversion reads every accessor through bounds-checked views.
#include "core/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "core/error.h"
#include "core/file_io.h"
#include "core/material_params.h"

namespace pv {
namespace {

using glm::dmat3;
using glm::dmat4;
using glm::dvec4;
using nlohmann::json;

// What pathview reads: a file may require these (KHR_mesh_quantization only widens the accessor types allowed,
// which the loader reads in every case). Anything else required is refused; anything else used is warned about.
const char* const kSupportedExtensions[] = {
    "KHR_materials_emissive_strength", "KHR_texture_transform", "KHR_materials_ior",   "KHR_materials_specular",
    "KHR_materials_transmission",      "KHR_materials_volume",  "KHR_lights_punctual", "KHR_mesh_quantization",
};

// tinygltf takes a file's size as a 32-bit unsigned int and copies every buffer once more: 2 GiB of file at most.
constexpr uint64_t kMaxGltfBytes = uint64_t(2) << 30;
// Node instances visited and triangles produced: a node hierarchy is a tree, but a file may reference a node twice
// and so instance a mesh exponentially often; these bound the work and the memory.
constexpr size_t kMaxNodeVisits = size_t(1) << 20;
constexpr size_t kMaxTriangles = size_t(1) << 27;
// What instancing may make of a file's bytes: a file may place a mesh many times, but a small file that would expand
// into gigabytes is refused. Vertices and triangles (each of them, counted with every instance) up to 2^22 or 16 per
// byte of the file's buffers, whichever is larger (each costs about 60 bytes in the scene).
constexpr size_t kMinInstancingBudget = size_t(1) << 22;
constexpr uint64_t kInstancingPerByte = 16;
constexpr float kMaxCoordinate = 1.844e18f;  // Embree ignores primitives beyond this (as obj_loader.cpp)

std::string ptr(std::initializer_list<std::string> parts) {
    std::string s;
    for (const std::string& p : parts) s += "/" + p;
    return s;
}
std::string str(size_t i) { return std::to_string(i); }

bool supported_extension(const std::string& name) {
    for (const char* e : kSupportedExtensions)
        if (name == e) return true;
    return false;
}

// %XX decoding of a relative URI (glTF URIs are percent-encoded).
std::string uri_decode(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// The bytes a base64 data URI decodes to (an upper bound when the text has stray characters); -1 if not base64.
int64_t data_uri_bytes(const std::string& uri) {
    const size_t comma = uri.find(',');
    if (comma == std::string::npos || uri.compare(0, 5, "data:") != 0) return -1;
    if (uri.rfind(";base64", comma) == std::string::npos) return -1;
    size_t n = uri.size() - comma - 1, pad = 0;
    for (size_t i = uri.size(); i > comma + 1 && uri[i - 1] == '='; --i) ++pad;
    return int64_t(n / 4 * 3) - int64_t(std::min<size_t>(pad, 2));
}

// The layout of a .glb: its JSON chunk and its BIN chunk (empty when absent), checked completely (tinygltf 2.7
// lets a BIN chunk's declared length reach 8 bytes past the file).
struct Glb {
    std::string_view json_text;
    uint64_t bin_size = 0;
    bool has_bin = false;
};

uint32_t le32(const std::string& b, size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}

Glb parse_glb(const std::string& bytes, const std::string& file) {
    if (bytes.size() < 20)
        throw Error(file + ": truncated .glb: " + str(bytes.size()) + " bytes; a binary glTF has at least 20");
    const uint32_t version = le32(bytes, 4), length = le32(bytes, 8);
    const uint32_t json_length = le32(bytes, 12), json_type = le32(bytes, 16);
    if (version != 2) throw Error(file + ": binary glTF version " + str(version) + "; expected 2");
    if (length > bytes.size())
        throw Error(file + ": truncated .glb: the header declares " + str(length) + " bytes, the file has " +
                    str(bytes.size()));
    if (json_length % 4 != 0)
        throw Error(file + ": .glb: the JSON chunk's length " + str(json_length) + " is not a multiple of 4");
    if (json_type != 0x4E4F534Au) throw Error(file + ": .glb: the first chunk is not JSON");
    if (json_length == 0 || 20ull + json_length > length)
        throw Error(file + ": truncated .glb: the JSON chunk declares " + str(json_length) + " bytes, " +
                    str(length >= 20 ? length - 20 : 0) + " follow the header");
    Glb g;
    g.json_text = std::string_view(bytes.data() + 20, json_length);
    const uint64_t bin_at = 20ull + json_length;
    if (bin_at + 8 <= length) {
        const uint32_t bin_length = le32(bytes, size_t(bin_at)), bin_type = le32(bytes, size_t(bin_at + 4));
        if (bin_type == 0x004E4942u) {
            if (bin_at + 8 + bin_length > length)
                throw Error(file + ": truncated .glb: the BIN chunk declares " + str(bin_length) + " bytes, " +
                            str(length - bin_at - 8) + " remain");
            g.bin_size = bin_length;
            g.has_bin = true;
        }
    }
    return g;
}

// tinygltf's file system: regular files of bounded size only, no path expansion.
struct FileAccess {
    std::string error;  // the last failure, for the message
};
bool fs_exists(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}
std::string fs_expand(const std::string& path, void*) { return path; }
bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    try {
        const std::string bytes = read_regular_file(path, kMaxGltfBytes, "a glTF buffer or image");
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const Error& e) {
        if (err) *err += e.what();
        static_cast<FileAccess*>(user)->error = e.what();
        return false;
    }
}
bool fs_write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

// A number from a tinygltf extension object (absent or not a number: `fallback`).
double value_number(const tinygltf::Value& o, const char* key, double fallback) {
    if (!o.IsObject() || !o.Has(key)) return fallback;
    const tinygltf::Value& v = o.Get(key);
    return v.IsNumber() || v.IsInt() ? v.GetNumberAsDouble() : fallback;
}
bool value_numbers(const tinygltf::Value& o, const char* key, double* out, int n) {
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
const tinygltf::Value* extension(const tinygltf::ExtensionMap& m, const char* name) {
    const auto it = m.find(name);
    return it == m.end() || !it->second.IsObject() ? nullptr : &it->second;
}

float finite_or(double v, float fallback) { return std::isfinite(v) ? float(v) : fallback; }

// A glTF UvTransform (in glTF's uv space, v down) as pathview's uv space sees it (v up, as OBJ): flip, transform,
// flip back; F(T(F(uv))) with F(w) = (w.x, 1 - w.y).
UvTransform to_pathview_uv(const UvTransform& t) {
    UvTransform r = t;
    r.col0 = vec2(t.col0.x, -t.col0.y);
    r.col1 = vec2(-t.col1.x, t.col1.y);
    r.offset = vec2(t.col1.x + t.offset.x, 1.f - (t.col1.y + t.offset.y));
    return r;
}

// The parameters of one glTF material, as the file gives them (the BSDF is built from them in one place).
struct GltfMaterial {
    vec4 base_color{1.f};
    float metallic = 1.f, roughness = 1.f;  // perceptual roughness
    float ior = 1.5f;
    float specular = 1.f;
    vec3 specular_color{1.f};
    float transmission = 0.f;
    float thickness = 0.f;  // KHR_materials_volume: 0 is thin-walled
    vec3 attenuation_color{1.f};
    float attenuation_distance = std::numeric_limits<float>::infinity();
};

// The BSDF of a glTF material: core/bsdf_pbr.h's MetallicRoughness, through make_bsdf (which clamps, and keeps only
// the lobes the parameters make non-zero).
Bsdf gltf_bsdf(const GltfMaterial& g) {
    BsdfParams p;
    p.type = BsdfType::MetallicRoughness;
    p.base = vec3(g.base_color);
    p.metallic = g.metallic;
    p.roughness = g.roughness;
    p.ior = g.ior;
    p.specular_weight = g.specular;
    p.specular = g.specular_color;
    p.transmission = g.transmission;
    p.thin_walled = !(g.thickness > 0.f);
    p.attenuation_color = g.attenuation_color;
    p.attenuation_distance = g.attenuation_distance;
    return make_bsdf(p);
}

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
    std::map<int, uint32_t> image_texture;  // glTF image -> Scene::textures index (as decoded)
    std::set<std::string> warned;           // one warning per kind

    size_t budget = kMinInstancingBudget;  // vertices and triangles at most (set from the buffers' size)
    size_t skipped_points_lines = 0, dropped_nonfinite = 0, dropped_degenerate = 0, visits = 0;
    bool non_white_colors = false;

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
            // Indices up to 2^32 - 1 are exact in double but not in float; read them again exactly.
            out[i] = uint32_t(f[i]);
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
    uint32_t image_texture_index(int image);
    uint32_t texture_of(const tinygltf::TextureInfo& info, const std::string& at, UvTransform& uv);
    void convert_materials();
    uint32_t material_index(int gltf_material, const std::string& at);
    void convert_cameras();
    void check_extensions();
};

// ---- Traversal: the default scene's nodes, depth first, each with its world transform. ----

void Loader::traverse(int scene_index) {
    struct Item {
        int node;
        dmat4 parent;
        std::string at;  // the JSON path that referred to the node
        bool exit;
    };
    std::vector<uint8_t> on_path(model.nodes.size(), 0);
    std::vector<Item> stack;
    const auto& roots = model.scenes[size_t(scene_index)].nodes;
    for (size_t i = roots.size(); i-- > 0;)
        stack.push_back({roots[i], dmat4(1.0), ptr({"scenes", str(size_t(scene_index)), "nodes", str(i)}), false});
    while (!stack.empty()) {
        Item it = std::move(stack.back());
        stack.pop_back();
        if (it.exit) {
            on_path[size_t(it.node)] = 0;
            continue;
        }
        if (it.node < 0 || size_t(it.node) >= model.nodes.size())
            fail(it.at, "node " + std::to_string(it.node) + " does not exist; the file has " + str(model.nodes.size()));
        const size_t n = size_t(it.node);
        if (on_path[n]) fail(it.at, "node " + str(n) + " is its own ancestor (a cycle in the node hierarchy)");
        if (++visits > kMaxNodeVisits)
            fail(it.at, "more than " + str(kMaxNodeVisits) + " node instances (nodes referenced more than once)");
        const tinygltf::Node& node = model.nodes[n];
        const dmat4 world = it.parent * local_transform(node, n);
        on_path[n] = 1;
        stack.push_back({it.node, dmat4(1.0), std::string(), true});
        for (size_t c = node.children.size(); c-- > 0;)
            stack.push_back({node.children[c], world, ptr({"nodes", str(n), "children", str(c)}), false});
        if (node.mesh >= 0) add_mesh(node.mesh, world, ptr({"nodes", str(n), "mesh"}));
        if (node.camera >= 0) {
            if (size_t(node.camera) >= model.cameras.size())
                fail(ptr({"nodes", str(n), "camera"}), "camera " + std::to_string(node.camera) + " does not exist");
            cameras.push_back({node.camera, it.node, world});
        }
        if (const tinygltf::Value* l = extension(node.extensions, "KHR_lights_punctual"))
            add_light(int(value_number(*l, "light", -1.0)), world,
                      ptr({"nodes", str(n), "extensions", "KHR_lights_punctual", "light"}));
    }
}

void Loader::add_light(int light, const dmat4& world, const std::string& at) {
    if (light < 0 || size_t(light) >= model.lights.size())
        fail(at, "light " + std::to_string(light) + " does not exist; the file has " + str(model.lights.size()));
    const tinygltf::Light& l = model.lights[size_t(light)];
    PunctualLight p;
    p.name = l.name;
    if (l.type == "point") {
        p.type = PunctualLight::Type::Point;
    } else if (l.type == "spot") {
        p.type = PunctualLight::Type::Spot;
    } else if (l.type == "directional") {
        p.type = PunctualLight::Type::Directional;
    } else {
        warn_once("light type " + l.type, ptr({"extensions", "KHR_lights_punctual", "lights", str(size_t(light))}) +
                                              ": unknown light type '" + l.type + "'; light ignored");
        return;
    }
    p.position = vec3(world * dvec4(0.0, 0.0, 0.0, 1.0));
    const dvec3 d = dmat3(world) * dvec3(0.0, 0.0, -1.0);
    const double len = glm::length(d);
    if (!(len > 0.0) || !std::isfinite(len) || !is_finite(p.position)) {
        warn_once("light transform", at + ": a light's transform is degenerate; light ignored");
        return;
    }
    p.direction = vec3(d / len);
    vec3 color(1.f);
    if (l.color.size() == 3)
        color = vec3(finite_or(l.color[0], 0.f), finite_or(l.color[1], 0.f), finite_or(l.color[2], 0.f));
    p.intensity = glm::max(color * finite_or(l.intensity, 0.f), vec3(0.f));
    p.range = l.range > 0.0 && std::isfinite(l.range) ? float(l.range) : 0.f;
    p.outer_cone_rad = glm::clamp(finite_or(l.spot.outerConeAngle, 0.7853981634f), 0.f, 1.5707963268f);
    p.inner_cone_rad = glm::clamp(finite_or(l.spot.innerConeAngle, 0.f), 0.f, p.outer_cone_rad);
    scene->punctual_lights.push_back(p);
}

// ---- Meshes ----

void Loader::add_mesh(int mesh_index, const dmat4& world, const std::string& ref_at) {
    if (mesh_index < 0 || size_t(mesh_index) >= model.meshes.size())
        fail(ref_at,
             "mesh " + std::to_string(mesh_index) + " does not exist; the file has " + str(model.meshes.size()));
    Scene& s = *scene;
    const tinygltf::Mesh& mesh = model.meshes[size_t(mesh_index)];
    const dmat3 m3(world);
    const double det = glm::determinant(m3);
    const dmat3 normal_matrix = glm::transpose(glm::inverse(m3));
    const bool flip = det < 0.0;
    for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
        const tinygltf::Primitive& prim = mesh.primitives[pi];
        const std::string at = ptr({"meshes", str(size_t(mesh_index)), "primitives", str(pi)});
        const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
        if (mode <= TINYGLTF_MODE_LINE_STRIP) {
            ++skipped_points_lines;
            continue;
        }
        if (mode > TINYGLTF_MODE_TRIANGLE_FAN) fail(at + "/mode", "mode " + std::to_string(mode) + "; expected 0..6");
        const auto pos_it = prim.attributes.find("POSITION");
        if (pos_it == prim.attributes.end()) {
            warn_once("no POSITION", at + ": a primitive without POSITION; skipped");
            continue;
        }
        int comps = 0;
        const std::vector<float> pos =
            read_floats(pos_it->second, at + "/attributes/POSITION", {TINYGLTF_TYPE_VEC3}, comps);
        const size_t nv = pos.size() / 3;
        auto attribute = [&](const char* name, std::initializer_list<int> types, int& c) -> std::vector<float> {
            const auto it = prim.attributes.find(name);
            if (it == prim.attributes.end()) return {};
            std::vector<float> v = read_floats(it->second, at + "/attributes/" + name, types, c);
            if (v.size() / size_t(c) != nv)
                fail(at + "/attributes/" + name,
                     "count " + str(v.size() / size_t(c)) + " differs from POSITION's " + str(nv));
            return v;
        };
        int nc = 0, tc0 = 0, tc1 = 0, cc = 0;
        const std::vector<float> nrm = attribute("NORMAL", {TINYGLTF_TYPE_VEC3}, nc);
        const std::vector<float> uv0 = attribute("TEXCOORD_0", {TINYGLTF_TYPE_VEC2}, tc0);
        const std::vector<float> uv1 = attribute("TEXCOORD_1", {TINYGLTF_TYPE_VEC2}, tc1);
        const std::vector<float> col = attribute("COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, cc);
        for (size_t i = 0; i < col.size(); ++i)
            if ((cc == 3 || i % 4 != 3) && col[i] != 1.f) non_white_colors = true;

        std::vector<uint32_t> idx;
        if (prim.indices >= 0) {
            idx = read_indices(prim.indices, at + "/indices", nv);
        } else {
            idx.resize(nv);
            for (size_t i = 0; i < nv; ++i) idx[i] = uint32_t(i);
        }
        // Triangles of the primitive (vertex numbers local to it), strips and fans as the specification orders them.
        std::vector<uvec3> tris;
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            for (size_t i = 0; i + 2 < idx.size(); i += 3) tris.push_back(uvec3(idx[i], idx[i + 1], idx[i + 2]));
        } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            for (size_t i = 0; i + 2 < idx.size(); ++i)
                tris.push_back(i % 2 == 0 ? uvec3(idx[i], idx[i + 1], idx[i + 2])
                                          : uvec3(idx[i + 1], idx[i], idx[i + 2]));
        } else {
            for (size_t i = 1; i + 1 < idx.size(); ++i) tris.push_back(uvec3(idx[i], idx[i + 1], idx[0]));
        }
        if (s.triangles.size() + tris.size() > budget || s.positions.size() + nv > budget)
            fail(at, "the scene would exceed " + str(budget) + " vertices or triangles (a mesh instanced by " +
                         str(visits) + " node visits; the limit is 16 per byte of the file's buffers, at least 2^22)");

        const uint32_t material = material_index(prim.material, at + "/material");
        const UvTransform& buv = prim.material >= 0 && size_t(prim.material) < base_uv.size()
                                     ? base_uv[size_t(prim.material)]
                                     : UvTransform{};
        // Vertices: world positions, normals by the inverse transpose, uvs flipped to pathview's v-up convention
        // (set 0 through the base colour texture's transform).
        const uint32_t p0 = uint32_t(s.positions.size());
        std::vector<uint8_t> bad(nv, 0);
        for (size_t i = 0; i < nv; ++i) {
            const vec3 p = vec3(world * dvec4(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], 1.0));
            const bool b = !is_finite(p) || max_component(glm::abs(p)) > kMaxCoordinate;
            bad[i] = b;
            s.positions.push_back(b ? vec3(0.f) : p);
        }
        const uint32_t n0 = uint32_t(s.normals.size());
        std::vector<uint8_t> bad_n(nrm.empty() ? 0 : nv, 0);
        for (size_t i = 0; i < nrm.size() / 3; ++i) {
            const dvec3 n = normal_matrix * dvec3(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
            const double l = glm::length(n);
            bad_n[i] = !(l > 1e-20) || !std::isfinite(l);
            s.normals.push_back(bad_n[i] ? vec3(0.f, 0.f, 1.f) : vec3(n / l));
        }
        const std::vector<float>& set0 = buv.set == 1 ? uv1 : uv0;
        const uint32_t t0 = uint32_t(s.uvs.size()), t1 = uint32_t(s.uvs1.size());
        for (size_t i = 0; i < set0.size() / 2; ++i) {
            const vec2 uv = buv.apply(vec2(set0[2 * i], set0[2 * i + 1]));
            s.uvs.push_back(vec2(uv.x, 1.f - uv.y));
        }
        for (size_t i = 0; i < uv1.size() / 2; ++i) s.uvs1.push_back(vec2(uv1[2 * i], 1.f - uv1[2 * i + 1]));

        for (uvec3 t : tris) {
            if (bad[t.x] || bad[t.y] || bad[t.z]) {
                ++dropped_nonfinite;
                continue;
            }
            if (flip) std::swap(t.y, t.z);  // a mirroring transform turns counter-clockwise faces clockwise
            const vec3 a = s.positions[p0 + t.x], b = s.positions[p0 + t.y], c = s.positions[p0 + t.z];
            const float area2 = glm::length(glm::cross(b - a, c - a));
            if (!(area2 > 0.f) || !std::isfinite(area2)) {
                ++dropped_degenerate;
                continue;
            }
            s.triangles.push_back(uvec3(p0) + t);
            s.material_ids.push_back(material);
            const bool normals_ok = !nrm.empty() && !bad_n[t.x] && !bad_n[t.y] && !bad_n[t.z];
            s.normal_indices.push_back(normals_ok ? uvec3(n0) + t : uvec3(kNoIndex));
            s.uv_indices.push_back(set0.empty() ? uvec3(kNoIndex) : uvec3(t0) + t);
            s.uv1_indices.push_back(uv1.empty() ? uvec3(kNoIndex) : uvec3(t1) + t);
        }
    }
}

// ---- Materials ----

uint32_t Loader::image_texture_index(int image) {
    if (auto it = image_texture.find(image); it != image_texture.end()) return it->second;
    const auto img = images.find(image);
    if (img == images.end()) return kNoIndex;
    scene->textures.push_back(img->second);
    const uint32_t id = uint32_t(scene->textures.size() - 1);
    image_texture[image] = id;
    return id;
}

// The decoded image a texture reference names (kNoIndex, with a warning, if none), and in `uv` its texture
// coordinate set and KHR_texture_transform (in glTF's uv space).
uint32_t Loader::texture_of(const tinygltf::TextureInfo& info, const std::string& at, UvTransform& uv) {
    uv = UvTransform{};
    if (info.index < 0) return kNoIndex;
    if (size_t(info.index) >= model.textures.size()) {
        warn_once(at, at + "/index: texture " + std::to_string(info.index) + " does not exist; flat colour used");
        return kNoIndex;
    }
    const tinygltf::Texture& texture = model.textures[size_t(info.index)];
    const int source = texture.source;
    if (texture.sampler >= 0 && size_t(texture.sampler) < model.samplers.size()) {
        const tinygltf::Sampler& sm = model.samplers[size_t(texture.sampler)];
        if (sm.wrapS != TINYGLTF_TEXTURE_WRAP_REPEAT || sm.wrapT != TINYGLTF_TEXTURE_WRAP_REPEAT)
            warn_once("wrap", ptr({"samplers", str(size_t(texture.sampler))}) +
                                  ": clamped or mirrored wrapping is not supported; textures repeat");
    }
    const uint32_t id = source >= 0 ? image_texture_index(source) : kNoIndex;
    if (id == kNoIndex) {
        warn_once(at, at + ": texture " + std::to_string(info.index) +
                          " has no decodable image (see the image's warning); flat colour used");
        return kNoIndex;
    }
    uv.set = info.texCoord == 1 ? 1u : 0u;
    if (info.texCoord > 1) warn_once(at + "texcoord", at + "/texCoord: only TEXCOORD_0 and _1 are read; 0 used");
    if (const tinygltf::Value* t = extension(info.extensions, "KHR_texture_transform")) {
        double off[2] = {0, 0}, sc[2] = {1, 1};
        value_numbers(*t, "offset", off, 2);
        value_numbers(*t, "scale", sc, 2);
        const float r = finite_or(value_number(*t, "rotation", 0.0), 0.f);
        const float c = std::cos(r), sn = std::sin(r);
        // uv' = offset + R (scale * uv), R = [c s; -s c] (the extension's matrix: a counter-clockwise rotation of
        // the uvs in glTF's v-down space).
        uv.col0 = finite_or(sc[0], 1.f) * vec2(c, -sn);
        uv.col1 = finite_or(sc[1], 1.f) * vec2(sn, c);
        uv.offset = vec2(finite_or(off[0], 0.f), finite_or(off[1], 0.f));
        const double set = value_number(*t, "texCoord", -1.0);
        if (set == 0.0 || set == 1.0) uv.set = uint32_t(set);
    }
    return id;
}

void Loader::convert_materials() {
    Scene& s = *scene;
    base_uv.assign(model.materials.size(), UvTransform{});
    for (size_t mi = 0; mi < model.materials.size(); ++mi) {
        const tinygltf::Material& gm = model.materials[mi];
        const std::string at = ptr({"materials", str(mi)});
        const auto& pbr = gm.pbrMetallicRoughness;
        GltfMaterial g;
        if (pbr.baseColorFactor.size() == 4)
            for (int c = 0; c < 4; ++c)
                g.base_color[c] = glm::clamp(finite_or(pbr.baseColorFactor[size_t(c)], 1.f), 0.f, 1.f);
        g.metallic = glm::clamp(finite_or(pbr.metallicFactor, 1.f), 0.f, 1.f);
        g.roughness = glm::clamp(finite_or(pbr.roughnessFactor, 1.f), 0.f, 1.f);
        if (const tinygltf::Value* e = extension(gm.extensions, "KHR_materials_ior")) {
            const float ior = finite_or(value_number(*e, "ior", 1.5), 1.5f);
            g.ior = ior >= 1.f ? ior : 1.5f;  // 0 (the extension's "no refraction" value) and below 1: default
        }
        if (const tinygltf::Value* e = extension(gm.extensions, "KHR_materials_specular")) {
            g.specular = glm::clamp(finite_or(value_number(*e, "specularFactor", 1.0), 1.f), 0.f, 1.f);
            double sc[3];
            if (value_numbers(*e, "specularColorFactor", sc, 3))
                g.specular_color =
                    glm::max(vec3(finite_or(sc[0], 1.f), finite_or(sc[1], 1.f), finite_or(sc[2], 1.f)), vec3(0.f));
        }
        if (const tinygltf::Value* e = extension(gm.extensions, "KHR_materials_transmission"))
            g.transmission = glm::clamp(finite_or(value_number(*e, "transmissionFactor", 0.0), 0.f), 0.f, 1.f);
        if (const tinygltf::Value* e = extension(gm.extensions, "KHR_materials_volume")) {
            g.thickness = std::max(finite_or(value_number(*e, "thicknessFactor", 0.0), 0.f), 0.f);
            double ac[3];
            if (value_numbers(*e, "attenuationColor", ac, 3))
                g.attenuation_color = glm::clamp(
                    vec3(finite_or(ac[0], 1.f), finite_or(ac[1], 1.f), finite_or(ac[2], 1.f)), vec3(0.f), vec3(1.f));
            const float d = finite_or(value_number(*e, "attenuationDistance", 0.0), 0.f);
            if (d > 0.f) g.attenuation_distance = d;
        }

        Material m;
        m.name = gm.name.empty() ? "material " + str(mi) : gm.name;
        // Base colour: the factor multiplies the texture (baked into a texture of its own when it is not white,
        // since Material::base_color_texture replaces the colour); alphaMode decides the cut-out.
        UvTransform buv;
        const uint32_t base_tex = texture_of(pbr.baseColorTexture, at + "/pbrMetallicRoughness/baseColorTexture", buv);
        const bool mask = gm.alphaMode == "MASK", blend = gm.alphaMode == "BLEND";
        const float cutoff = finite_or(gm.alphaCutoff, 0.5f);
        if (base_tex != kNoIndex) {
            base_uv[mi] = buv;
            const bool white = vec3(g.base_color) == vec3(1.f);
            const bool alpha_used = mask || (blend && (g.base_color.w < 1.f || s.textures[base_tex].has_alpha()));
            if (white && !alpha_used) {
                m.base_color_texture = base_tex;
            } else {
                const Texture& src = s.textures[base_tex];
                std::vector<vec4> texels = src.texels();
                for (vec4& t : texels) {
                    t = vec4(vec3(t) * vec3(g.base_color), t.w * g.base_color.w);
                    if (mask) t.w = t.w >= cutoff ? 1.f : 0.f;
                }
                s.textures.emplace_back(src.width(), src.height(), std::move(texels));
                m.base_color_texture = uint32_t(s.textures.size() - 1);
                if (alpha_used) m.alpha_texture = m.base_color_texture;
            }
        } else if ((mask && g.base_color.w < cutoff) || (blend && g.base_color.w < 1.f)) {
            // A constant opacity: a 1x1 texture of it (MASK below the cut-off: the surface is not there).
            const float a = mask ? 0.f : g.base_color.w;
            s.textures.emplace_back(1, 1, std::vector<vec4>{vec4(vec3(g.base_color), a)});
            m.alpha_texture = uint32_t(s.textures.size() - 1);
        }
        m.bsdf = gltf_bsdf(g);
        // Textures read by neither the BSDF nor the loader yet (occlusionTexture is not used on purpose: a path tracer
        // computes occlusion).
        if (pbr.metallicRoughnessTexture.index >= 0)
            warn_once("mr texture", "metallicRoughnessTexture is not used yet; the metallic and roughness factors are");
        if (gm.normalTexture.index >= 0) warn_once("normal texture", "normalTexture is not used yet");

        // Emission: emissiveFactor x KHR_materials_emissive_strength (x emissiveTexture).
        vec3 e(0.f);
        if (gm.emissiveFactor.size() == 3)
            e = glm::max(vec3(finite_or(gm.emissiveFactor[0], 0.f), finite_or(gm.emissiveFactor[1], 0.f),
                              finite_or(gm.emissiveFactor[2], 0.f)),
                         vec3(0.f));
        if (const tinygltf::Value* x = extension(gm.extensions, "KHR_materials_emissive_strength"))
            e *= std::max(finite_or(value_number(*x, "emissiveStrength", 1.0), 1.f), 0.f);
        m.emission = is_finite(e) ? e : vec3(0.f);
        if (m.has_emission()) {
            UvTransform euv;
            m.emissive_texture = texture_of(gm.emissiveTexture, at + "/emissiveTexture", euv);
            // Set 0 holds the base colour texture's uvs (their transform applied); set 1 holds TEXCOORD_1 as is.
            if (m.emissive_texture != kNoIndex) {
                if (euv == buv && base_tex != kNoIndex) {
                    m.emissive_uv = UvTransform{};
                } else if (euv.set == 1 || base_tex == kNoIndex || buv.is_identity()) {
                    m.emissive_uv = to_pathview_uv(euv);
                } else {
                    warn_once(at + "euv", at + "/emissiveTexture: its uv transform differs from the base colour "
                                               "texture's on TEXCOORD_0; the base colour's is used");
                    m.emissive_uv = UvTransform{};
                }
            }
        }
        m.two_sided_emission = gm.doubleSided;
        s.materials.push_back(std::move(m));
    }
}

uint32_t Loader::material_index(int gltf_material, const std::string& at) {
    if (gltf_material >= 0 && size_t(gltf_material) < model.materials.size()) return uint32_t(gltf_material);
    if (gltf_material >= 0)
        warn_once("bad material",
                  at + ": material " + std::to_string(gltf_material) + " does not exist; the default material is used");
    if (default_material == kNoIndex) {
        // glTF's default material: white, metallic 1, roughness 1 (the specification's defaults). pathview uses
        // its own default grey diffuse instead, as for an OBJ face without a material.
        default_material = uint32_t(scene->materials.size());
        scene->materials.push_back(Material{});
    }
    return default_material;
}

// ---- Cameras ----

void Loader::convert_cameras() {
    Scene& s = *scene;
    vec3 lo, hi;
    s.bounds(lo, hi);
    const vec3 centre = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    std::set<std::string> names;
    bool first = true;
    for (size_t i = 0; i < cameras.size(); ++i) {
        const CameraInstance& ci = cameras[i];
        const tinygltf::Camera& c = model.cameras[size_t(ci.camera)];
        if (c.type != "perspective") {
            warn_once("ortho", ptr({"cameras", str(size_t(ci.camera))}) + ": camera type '" + c.type +
                                   "' is not supported (perspective only); camera ignored");
            continue;
        }
        const vec3 eye = vec3(ci.world * dvec4(0.0, 0.0, 0.0, 1.0));
        const dvec3 fwd = dmat3(ci.world) * dvec3(0.0, 0.0, -1.0);
        const dvec3 up = dmat3(ci.world) * dvec3(0.0, 1.0, 0.0);
        if (!is_finite(eye) || !(glm::length(fwd) > 0.0) || !(glm::length(up) > 0.0)) {
            warn_once("camera transform",
                      ptr({"nodes", str(size_t(ci.node))}) + ": the camera's transform is degenerate; camera ignored");
            continue;
        }
        CameraDesc d;
        d.eye = eye;
        const vec3 f = vec3(glm::normalize(fwd));
        // The target: the scene's centre projected on the view axis (the viewer orbits about it), at least a
        // hundredth of the scene's size ahead.
        d.target = eye + f * std::max(glm::dot(centre - eye, f), 0.01f * radius);
        d.up = vec3(glm::normalize(up));
        const double yfov = c.perspective.yfov;
        d.vfov_deg = std::isfinite(yfov) && yfov > 0.0 ? glm::clamp(float(glm::degrees(yfov)), 0.01f, 179.f) : 40.f;
        std::string name = !c.name.empty()                              ? c.name
                           : !model.nodes[size_t(ci.node)].name.empty() ? model.nodes[size_t(ci.node)].name
                                                                        : "camera " + str(size_t(ci.camera));
        for (int k = 2; !names.insert(name).second; ++k) name = name + " (" + std::to_string(k) + ")";
        s.bookmarks.push_back(Scene::Bookmark{name, d});
        if (first) {
            s.camera = d;
            s.has_camera = true;
            first = false;
        }
    }
}

void Loader::check_extensions() {
    for (const std::string& e : model.extensionsUsed)
        if (!supported_extension(e)) warn_once("ext " + e, "extension '" + e + "' is used but not supported; ignored");
}

// The checks before tinygltf: required extensions, each buffer's source and declared size (a missing file, a size
// that the file, data URI or BIN chunk does not hold), with JSON paths.
void precheck(const std::string_view json_text, const std::string& file, const std::string& dir, const Glb* glb) {
    const json j = json::parse(json_text.begin(), json_text.end(), nullptr, false);
    if (j.is_discarded()) throw Error(file + ": invalid JSON");
    if (!j.is_object()) throw Error(file + ": /: expected a JSON object");
    if (j.contains("extensionsRequired") && j["extensionsRequired"].is_array()) {
        const json& req = j["extensionsRequired"];
        for (size_t i = 0; i < req.size(); ++i)
            if (req[i].is_string() && !supported_extension(req[i].get<std::string>()))
                throw Error(file + ": /extensionsRequired/" + str(i) + ": the file requires extension '" +
                            req[i].get<std::string>() + "', which pathview does not support");
    }
    if (!j.contains("buffers")) return;
    const json& buffers = j["buffers"];
    if (!buffers.is_array()) throw Error(file + ": /buffers: expected an array");
    for (size_t i = 0; i < buffers.size(); ++i) {
        const std::string at = "/buffers/" + str(i);
        const json& b = buffers[i];
        if (!b.is_object()) throw Error(file + ": " + at + ": expected an object");
        if (!b.contains("byteLength") || !b["byteLength"].is_number_unsigned())
            throw Error(file + ": " + at + "/byteLength: expected a non-negative integer");
        const uint64_t declared = b["byteLength"].get<uint64_t>();
        auto too_big = [&](const std::string& where, uint64_t has) {
            throw Error(file + ": " + at + "/byteLength: declares " + str(declared) + " bytes, but " + where +
                        " holds " + str(has));
        };
        if (!b.contains("uri")) {
            if (!glb || i != 0) throw Error(file + ": " + at + "/uri: missing; only a .glb's first buffer may omit it");
            if (!glb->has_bin) throw Error(file + ": " + at + ": the .glb has no BIN chunk for this buffer");
            if (declared > glb->bin_size) too_big("the BIN chunk", glb->bin_size);
            continue;
        }
        if (!b["uri"].is_string()) throw Error(file + ": " + at + "/uri: expected a string");
        const std::string uri = b["uri"].get<std::string>();
        if (uri.compare(0, 5, "data:") == 0) {
            const int64_t n = data_uri_bytes(uri);
            if (n < 0) throw Error(file + ": " + at + "/uri: a data URI that is not base64");
            if (uint64_t(n) < declared) too_big("its data URI", uint64_t(n));
            continue;
        }
        const std::string path = (std::filesystem::path(dir) / uri_decode(uri)).string();
        std::error_code ec;
        if (!std::filesystem::exists(path, ec))
            throw Error(file + ": " + at + "/uri: '" + uri + "' not found (looked for " + path + ")");
        const uint64_t size = regular_file_size(path, "a glTF buffer (.bin)");
        if (size != declared)
            throw Error(file + ": " + at + "/byteLength: declares " + str(declared) + " bytes, but '" + uri + "' has " +
                        str(size));
    }
}

// tinygltf's messages on one line: its lines joined, cut at 300 characters.
std::string one_line(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ';';
    if (s.size() > 300) s = s.substr(0, 300) + "...";
    return s;
}

struct ImageContext {
    Loader* loader;
};

bool decode_image(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
                  const unsigned char* bytes, int size, void* user) {
    Loader& L = *static_cast<ImageContext*>(user)->loader;
    const std::string at = ptr({"images", std::to_string(index)});
    if (image->bufferView >= 0) {
        // tinygltf hands over &buffer[view.byteOffset] for view.byteLength bytes without checking either: check
        // that the view lies in its buffer before a byte is read.
        const auto& views = L.model.bufferViews;
        bool ok = size_t(image->bufferView) < views.size();
        if (ok) {
            const tinygltf::BufferView& bv = views[size_t(image->bufferView)];
            ok = bv.buffer >= 0 && size_t(bv.buffer) < L.model.buffers.size();
            if (ok) {
                const uint64_t n = L.model.buffers[size_t(bv.buffer)].data.size();
                ok = bv.byteOffset <= n && bv.byteLength <= n - bv.byteOffset;
            }
        }
        if (!ok) {
            if (err) *err += at + "/bufferView: the image's bytes lie outside its buffer";
            return false;
        }
    }
    if (!bytes || size <= 0) {
        L.warnings.push_back(L.file + ": " + at + ": no image data; flat colour used");
        return true;
    }
    try {
        L.images[index] = Texture::decode(std::string(reinterpret_cast<const char*>(bytes), size_t(size)),
                                          L.file + ": " + at + (image->uri.empty() ? "" : " (" + image->uri + ")"),
                                          false, &L.warnings);
    } catch (const Error& e) {
        L.warnings.push_back(std::string(e.what()) + "; flat colour used");
    }
    return true;
}

Scene load(const std::string& bytes, const std::string& file) {
    std::string dir = std::filesystem::path(file).parent_path().string();
    if (dir.empty()) dir = ".";
    const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    std::string ext = std::filesystem::path(file).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (!binary && ext == ".glb") {
        std::string magic;
        for (size_t i = 0; i < std::min<size_t>(4, bytes.size()); ++i)
            magic += std::isprint(static_cast<unsigned char>(bytes[i])) ? bytes[i] : '?';
        throw Error(file + ": not a binary glTF: it starts with '" + magic + "'; expected the magic 'glTF'");
    }
    if (bytes.size() > kMaxGltfBytes) throw Error(file + ": larger than 2 GiB; expected a glTF file");
    Glb glb;
    if (binary) glb = parse_glb(bytes, file);
    precheck(binary ? glb.json_text : std::string_view(bytes), file, dir, binary ? &glb : nullptr);

    Scene scene;
    scene.source = file;
    Loader L(file, scene);
    tinygltf::TinyGLTF gltf;
    FileAccess access;
    gltf.SetFsCallbacks(tinygltf::FsCallbacks{fs_exists, fs_expand, fs_read, fs_write, &access});
    ImageContext images{&L};
    gltf.SetImageLoader(decode_image, &images);
    std::string err, warn;
    bool ok = false;
    try {
        if (binary)
            ok = gltf.LoadBinaryFromMemory(&L.model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                           static_cast<unsigned int>(bytes.size()), dir);
        else
            ok = gltf.LoadASCIIFromString(&L.model, &err, &warn, bytes.data(), static_cast<unsigned int>(bytes.size()),
                                          dir);
    } catch (const std::exception& e) {
        throw Error(file + ": cannot parse glTF: " + one_line(e.what()));
    }
    if (!ok) throw Error(file + ": cannot parse glTF: " + one_line(err.empty() ? "unknown error" : err));
    if (!warn.empty()) scene.warnings.push_back(file + ": " + one_line(warn));
    L.check_extensions();

    uint64_t buffer_bytes = 0;
    for (const auto& b : L.model.buffers) buffer_bytes += b.data.size();
    L.budget = size_t(
        std::min<uint64_t>(kMaxTriangles, std::max<uint64_t>(kMinInstancingBudget, kInstancingPerByte * buffer_bytes)));
    L.convert_materials();
    if (!L.model.scenes.empty()) {
        int si = L.model.defaultScene;
        if (si < 0 || size_t(si) >= L.model.scenes.size()) si = 0;
        L.traverse(si);
    } else if (!L.model.nodes.empty()) {
        scene.warnings.push_back(file + ": the file has no scene; nothing to show");
    }
    if (L.skipped_points_lines)
        scene.warnings.push_back(file + ": " + str(L.skipped_points_lines) +
                                 " point or line primitive(s) skipped (triangles only)");
    if (L.dropped_nonfinite)
        scene.warnings.push_back(file + ": " + str(L.dropped_nonfinite) +
                                 " triangle(s) with non-finite or absurd (> 1e18) vertices dropped");
    if (L.dropped_degenerate)
        scene.warnings.push_back(file + ": " + str(L.dropped_degenerate) + " zero-area triangle(s) dropped");
    if (L.non_white_colors)
        scene.warnings.push_back(file + ": COLOR_0 (vertex colours) is not used: pathview has no per-vertex colour");
    scene.stats.dropped_nonfinite = L.dropped_nonfinite;
    scene.stats.dropped_degenerate = L.dropped_degenerate;
    // Per-triangle arrays all-absent are dropped (the scene then pays nothing for them).
    auto all_absent = [](const std::vector<uvec3>& v) {
        return std::all_of(v.begin(), v.end(), [](const uvec3& t) { return t.x == kNoIndex; });
    };
    if (all_absent(scene.normal_indices)) scene.normal_indices.clear(), scene.normals.clear();
    if (all_absent(scene.uv_indices)) scene.uv_indices.clear(), scene.uvs.clear();
    if (all_absent(scene.uv1_indices)) scene.uv1_indices.clear(), scene.uvs1.clear();
    if (scene.triangles.empty()) scene.warnings.push_back(file + ": the scene has no triangles");
    L.convert_cameras();
    if (!scene.has_camera) scene.camera = scene.framing_camera();
    return scene;
}

}  // namespace

bool is_gltf_path(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".gltf" || ext == ".glb";
}

Scene load_gltf(const std::string& path) { return load(read_regular_file(path, kMaxGltfBytes, "a glTF file"), path); }

Scene load_gltf_from_memory(const std::string& bytes, const std::string& name) { return load(bytes, name); }

}  // namespace pv
