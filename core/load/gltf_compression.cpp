// core/load/gltf_compression.cpp: EXT_meshopt_compression and KHR_draco_mesh_compression decoded into the loader's
// tinygltf model (see gltf_compression.h).
#include "core/load/gltf_compression.h"

#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include <nlohmann/json.hpp>

#include "core/load/gltf_internal.h"
#include "core/load/json_bounds.h"

namespace pv::gltf_detail {

namespace {

using nlohmann::json;

uint32_t read_u32(const std::string& s, size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, s.data() + at, 4);
    return v;
}
void put_u32(std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }

bool has_extension(const json& o, const char* name) {
    return o.is_object() && o.contains("extensions") && o["extensions"].is_object() && o["extensions"].contains(name) &&
           o["extensions"][name].is_object();
}

// Replaces fallback buffers and drops Draco primitives' "indices" in a parsed glTF JSON; returns whether anything
// changed.
bool replace_fallbacks(json& j) {
    if (!j.is_object()) return false;
    bool changed = false;
    if (j.contains("meshes") && j["meshes"].is_array())
        for (json& m : j["meshes"]) {
            if (!m.is_object() || !m.contains("primitives") || !m["primitives"].is_array()) continue;
            for (json& p : m["primitives"])
                if (has_extension(p, "KHR_draco_mesh_compression") && p.contains("indices")) {
                    p.erase("indices");
                    changed = true;
                }
        }
    if (!j.contains("buffers") || !j["buffers"].is_array()) return changed;
    for (json& b : j["buffers"]) {
        if (!b.is_object() || b.contains("uri") || !b.contains("extensions") || !b["extensions"].is_object()) continue;
        const json& ext = b["extensions"];
        if (!ext.contains("EXT_meshopt_compression") || !ext["EXT_meshopt_compression"].is_object()) continue;
        const json& e = ext["EXT_meshopt_compression"];
        if (!e.contains("fallback") || e["fallback"] != true) continue;
        b["uri"] = "data:application/octet-stream;base64,AA==";
        b["byteLength"] = 1;
        changed = true;
    }
    return changed;
}

}  // namespace

bool compressed_json_fixups(const std::string& bytes, const std::string& file, std::string& out) {
    const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    if (!binary) {
        if (bytes.find("EXT_meshopt_compression") == std::string::npos &&
            bytes.find("KHR_draco_mesh_compression") == std::string::npos)
            return false;
        check_json_bounds(bytes, file, gltf_json_bounds());  // before nlohmann recurses into it
        json j = json::parse(bytes, nullptr, false);
        if (j.is_discarded() || !replace_fallbacks(j)) return false;
        out = j.dump();
        return true;
    }
    // GLB: 12-byte header, then the JSON chunk (length, type, text), then the rest (the BIN chunk) as it is. Anything
    // malformed is left to the loader's own GLB checks.
    if (bytes.size() < 20) return false;
    const uint64_t json_len = read_u32(bytes, 12);
    if (read_u32(bytes, 16) != 0x4E4F534Au || json_len > bytes.size() - 20) return false;
    const std::string_view text(bytes.data() + 20, size_t(json_len));
    if (text.find("EXT_meshopt_compression") == std::string_view::npos &&
        text.find("KHR_draco_mesh_compression") == std::string_view::npos)
        return false;
    check_json_bounds(text, file, gltf_json_bounds());
    json j = json::parse(text.begin(), text.end(), nullptr, false);
    if (j.is_discarded() || !replace_fallbacks(j)) return false;
    std::string new_text = j.dump();
    while (new_text.size() % 4) new_text += ' ';
    const size_t rest = bytes.size() - 20 - size_t(json_len);
    out = bytes.substr(0, 8);
    put_u32(out, uint32_t(12 + 8 + new_text.size() + rest));
    put_u32(out, uint32_t(new_text.size()));
    put_u32(out, 0x4E4F534Au);
    out += new_text;
    out.append(bytes, 20 + size_t(json_len), rest);
    return true;
}

namespace {

std::string value_string(const tinygltf::Value& o, const char* key, const std::string& fallback) {
    if (!o.IsObject() || !o.Has(key)) return fallback;
    const tinygltf::Value& v = o.Get(key);
    return v.IsString() ? v.Get<std::string>() : fallback;
}

// A non-negative integer property (absent: `fallback`; present and not one: refused).
uint64_t value_count(const Loader& L, const tinygltf::Value& o, const char* key, uint64_t fallback,
                     const std::string& at) {
    if (!o.Has(key)) return fallback;
    const tinygltf::Value& v = o.Get(key);
    const double d = v.IsNumber() || v.IsInt() ? v.GetNumberAsDouble() : -1.0;
    if (!(d >= 0.0) || d > 9007199254740992.0 || d != std::floor(d))
        L.fail(at + "/" + key, "expected a non-negative integer");
    return uint64_t(d);
}

struct Budget {
    uint64_t left;
    void take(const Loader& L, uint64_t bytes, const std::string& at, uint64_t limit) {
        if (bytes > left)
            L.fail(at, "decodes to " + str(bytes) + " bytes, past the file's budget of " + str(limit) +
                           " decoded bytes (" + str(kDecodedPerByte) + " per byte of its buffers, at least " +
                           str(kMinDecodedBytes) + ")");
        left -= bytes;
    }
};

// The source bytes [offset, offset + length) of buffer `buffer`, checked.
const uint8_t* source_bytes(const Loader& L, uint64_t buffer, uint64_t offset, uint64_t length, const std::string& at) {
    if (buffer >= L.model.buffers.size())
        L.fail(at + "/buffer",
               "buffer " + str(buffer) + " does not exist; the file has " + str(L.model.buffers.size()));
    const uint64_t n = L.model.buffers[size_t(buffer)].data.size();
    if (offset > n || length > n - offset)
        L.fail(at, "bytes " + str(offset) + " + " + str(length) + " lie past the end of buffer " + str(buffer) +
                       ", which has " + str(n));
    return L.model.buffers[size_t(buffer)].data.data() + offset;
}

void decode_meshopt_view(Loader& L, size_t view, Budget& budget, uint64_t limit) {
    tinygltf::BufferView& bv = L.model.bufferViews[view];
    const tinygltf::Value* e = extension(bv.extensions, "EXT_meshopt_compression");
    if (!e) return;
    const std::string at = ptr({"bufferViews", str(view), "extensions", "EXT_meshopt_compression"});
    if (!e->Has("buffer")) L.fail(at + "/buffer", "missing");
    const uint64_t buffer = value_count(L, *e, "buffer", 0, at);
    const uint64_t offset = value_count(L, *e, "byteOffset", 0, at);
    if (!e->Has("byteLength")) L.fail(at + "/byteLength", "missing");
    const uint64_t length = value_count(L, *e, "byteLength", 0, at);
    if (!e->Has("byteStride")) L.fail(at + "/byteStride", "missing");
    const uint64_t stride = value_count(L, *e, "byteStride", 0, at);
    if (!e->Has("count")) L.fail(at + "/count", "missing");
    const uint64_t count = value_count(L, *e, "count", 0, at);
    const std::string mode = value_string(*e, "mode", "");
    const std::string filter = value_string(*e, "filter", "NONE");
    const uint8_t* src = source_bytes(L, buffer, offset, length, at);
    if (mode == "ATTRIBUTES") {
        if (stride == 0 || stride > 256 || stride % 4)
            L.fail(at + "/byteStride", "byteStride " + str(stride) + "; ATTRIBUTES need a multiple of 4 up to 256");
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
        if (stride != 2 && stride != 4)
            L.fail(at + "/byteStride", "byteStride " + str(stride) + "; " + mode + " need 2 or 4");
        if (mode == "TRIANGLES" && count % 3)
            L.fail(at + "/count", "count " + str(count) + " is not a multiple of 3 (TRIANGLES)");
    } else {
        L.fail(at + "/mode", "mode '" + mode + "'; expected ATTRIBUTES, TRIANGLES or INDICES");
    }
    if (filter != "NONE" && mode != "ATTRIBUTES")
        L.fail(at + "/filter", "filter '" + filter + "' on " + mode + "; filters apply to ATTRIBUTES only");
    if (count > (uint64_t(1) << 40)) L.fail(at + "/count", "count " + str(count) + " is absurd");
    const uint64_t size = count * stride;
    if (size > bv.byteLength)
        L.fail(at + "/count", "count " + str(count) + " x byteStride " + str(stride) + " = " + str(size) +
                                  " bytes, past the buffer view's byteLength " + str(bv.byteLength));
    budget.take(L, bv.byteLength, at, limit);
    tinygltf::Buffer out;
    out.data.resize(size_t(bv.byteLength));
    int rc = 0;
    if (mode == "ATTRIBUTES")
        rc = meshopt_decodeVertexBuffer(out.data.data(), size_t(count), size_t(stride), src, size_t(length));
    else if (mode == "TRIANGLES")
        rc = meshopt_decodeIndexBuffer(out.data.data(), size_t(count), size_t(stride), src, size_t(length));
    else
        rc = meshopt_decodeIndexSequence(out.data.data(), size_t(count), size_t(stride), src, size_t(length));
    if (rc != 0)
        L.fail(at, "the compressed " + mode + " data is malformed or truncated (meshoptimizer error " +
                       std::to_string(rc) + ")");
    if (filter == "OCTAHEDRAL") {
        if (stride != 4 && stride != 8) L.fail(at + "/filter", "OCTAHEDRAL needs byteStride 4 or 8");
        meshopt_decodeFilterOct(out.data.data(), size_t(count), size_t(stride));
    } else if (filter == "QUATERNION") {
        if (stride != 8) L.fail(at + "/filter", "QUATERNION needs byteStride 8");
        meshopt_decodeFilterQuat(out.data.data(), size_t(count), size_t(stride));
    } else if (filter == "EXPONENTIAL") {
        meshopt_decodeFilterExp(out.data.data(), size_t(count), size_t(stride));
    } else if (filter != "NONE") {
        L.fail(at + "/filter", "filter '" + filter + "'; expected NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
    }
    L.model.buffers.push_back(std::move(out));
    bv.buffer = int(L.model.buffers.size() - 1);
    bv.byteOffset = 0;
    bv.extensions.erase("EXT_meshopt_compression");
}

// A new buffer, view and accessor holding `data` (count elements of `type`, float or uint32 components).
int add_accessor(Loader& L, std::vector<unsigned char> data, size_t count, int type, int component_type) {
    tinygltf::Buffer b;
    const size_t n = data.size();
    b.data = std::move(data);
    L.model.buffers.push_back(std::move(b));
    tinygltf::BufferView v;
    v.buffer = int(L.model.buffers.size() - 1);
    v.byteOffset = 0;
    v.byteLength = n;
    L.model.bufferViews.push_back(v);
    tinygltf::Accessor a;
    a.bufferView = int(L.model.bufferViews.size() - 1);
    a.byteOffset = 0;
    a.count = count;
    a.type = type;
    a.componentType = component_type;
    a.normalized = false;
    L.model.accessors.push_back(a);
    return int(L.model.accessors.size() - 1);
}

void decode_draco_primitive(Loader& L, size_t mi, size_t pi, Budget& budget, uint64_t limit) {
    tinygltf::Primitive& prim = L.model.meshes[mi].primitives[pi];
    const tinygltf::Value* e = extension(prim.extensions, "KHR_draco_mesh_compression");
    if (!e) return;
    const std::string at = ptr({"meshes", str(mi), "primitives", str(pi), "extensions", "KHR_draco_mesh_compression"});
    if (!e->Has("bufferView")) L.fail(at + "/bufferView", "missing");
    const uint64_t view = value_count(L, *e, "bufferView", 0, at);
    if (view >= L.model.bufferViews.size())
        L.fail(at + "/bufferView",
               "bufferView " + str(view) + " does not exist; the file has " + str(L.model.bufferViews.size()));
    const tinygltf::BufferView& bv = L.model.bufferViews[size_t(view)];
    if (bv.buffer < 0) L.fail(ptr({"bufferViews", str(size_t(view)), "buffer"}), "missing");
    const uint8_t* src =
        source_bytes(L, uint64_t(bv.buffer), bv.byteOffset, bv.byteLength, ptr({"bufferViews", str(size_t(view))}));
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP)
        L.fail(at, "a Draco primitive must be triangles or a triangle strip");
    if (!e->Has("attributes") || !e->Get("attributes").IsObject()) L.fail(at + "/attributes", "expected an object");
    const tinygltf::Value& attrs = e->Get("attributes");

    draco::DecoderBuffer db;
    db.Init(reinterpret_cast<const char*>(src), size_t(bv.byteLength));
    const auto type = draco::Decoder::GetEncodedGeometryType(&db);
    if (!type.ok()) L.fail(at, "not a Draco stream: " + type.status().error_msg_string());
    if (type.value() != draco::TRIANGULAR_MESH) L.fail(at, "the Draco stream is a point cloud, not a triangle mesh");
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&db);
    if (!decoded.ok()) L.fail(at, "the Draco stream is malformed or truncated: " + decoded.status().error_msg_string());
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    const size_t np = mesh->num_points(), nf = mesh->num_faces();

    for (const std::string& name : attrs.Keys()) {
        const std::string a_at = at + "/attributes/" + name;
        const auto it = prim.attributes.find(name);
        if (it == prim.attributes.end())
            L.fail(a_at, "attribute '" + name + "' is not among the primitive's attributes");
        if (it->second < 0 || size_t(it->second) >= L.model.accessors.size())
            L.fail(ptr({"meshes", str(mi), "primitives", str(pi), "attributes", name}),
                   "accessor " + std::to_string(it->second) + " does not exist");
        const tinygltf::Value& idv = attrs.Get(name);
        const double id = idv.IsNumber() || idv.IsInt() ? idv.GetNumberAsDouble() : -1.0;
        const draco::PointAttribute* pa =
            id >= 0.0 && id < 1e9 && id == std::floor(id) ? mesh->GetAttributeByUniqueId(uint32_t(id)) : nullptr;
        if (!pa) L.fail(a_at, "the Draco stream has no attribute with id " + json(id).dump());
        const int accessor_type = L.model.accessors[size_t(it->second)].type;
        const int nc = Loader::type_components(accessor_type);
        if (nc == 0 || pa->num_components() != nc)
            L.fail(a_at, "the Draco attribute has " + std::to_string(int(pa->num_components())) +
                             " components; the accessor's type has " + std::to_string(nc));
        budget.take(L, uint64_t(np) * uint64_t(nc) * 4, a_at, limit);
        std::vector<unsigned char> data(np * size_t(nc) * 4);
        float value[4];
        for (size_t p = 0; p < np; ++p) {
            if (!pa->ConvertValue<float>(pa->mapped_index(draco::PointIndex(uint32_t(p))), int8_t(nc), value))
                L.fail(a_at, "a Draco attribute value cannot be read as numbers");
            std::memcpy(data.data() + p * size_t(nc) * 4, value, size_t(nc) * 4);
        }
        it->second = add_accessor(L, std::move(data), np, accessor_type, TINYGLTF_COMPONENT_TYPE_FLOAT);
    }
    budget.take(L, uint64_t(nf) * 12, at, limit);
    std::vector<unsigned char> idx(nf * 12);
    for (size_t f = 0; f < nf; ++f) {
        const draco::Mesh::Face& face = mesh->face(draco::FaceIndex(uint32_t(f)));
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = face[k].value();
            std::memcpy(idx.data() + f * 12 + size_t(k) * 4, &v, 4);
        }
    }
    prim.indices = add_accessor(L, std::move(idx), nf * 3, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    prim.mode = TINYGLTF_MODE_TRIANGLES;  // Draco decodes a strip into a triangle list
    prim.extensions.erase("KHR_draco_mesh_compression");
}

}  // namespace

void decompress(Loader& L) {
    uint64_t buffer_bytes = 0;
    for (const auto& b : L.model.buffers) buffer_bytes += b.data.size();
    const uint64_t limit =
        std::min(kMaxGltfBytes, std::max(kMinDecodedBytes, kDecodedPerByte * std::min(buffer_bytes, kMaxGltfBytes)));
    Budget budget{limit};
    const size_t views = L.model.bufferViews.size();
    for (size_t v = 0; v < views; ++v) decode_meshopt_view(L, v, budget, limit);
    for (size_t m = 0; m < L.model.meshes.size(); ++m)
        for (size_t p = 0; p < L.model.meshes[m].primitives.size(); ++p) decode_draco_primitive(L, m, p, budget, limit);
}

}  // namespace pv::gltf_detail
