// core/load/gltf_loader.cpp: glTF 2.0 through tinygltf (see gltf_loader.h). A pre-pass over the JSON checks what
// tinygltf would read unchecked or report without a JSON path (required extensions, the buffers' sources and
// sizes, a .glb's chunk layout); tinygltf then parses, with pathview's own file reading and image decoding; the
// conversion reads every accessor through bounds-checked views. Nodes, meshes and lights: core/load/gltf_meshes.cpp;
// materials and cameras: core/load/gltf_materials.cpp.
#include "core/load/gltf_loader.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/load/gltf_compression.h"
#include "core/load/gltf_internal.h"
#include "core/load/json_bounds.h"
#include "core/scene/texture_decode.h"

namespace pv {
namespace gltf_detail {
namespace {

using nlohmann::json;

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

// A file's identity (device, inode): how a path tinygltf opens is matched with a buffer precheck() saw.
std::pair<uint64_t, uint64_t> file_id(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return {0, 0};
    return {uint64_t(st.st_dev), uint64_t(st.st_ino)};
}

// tinygltf's file system: regular files of bounded size only, no path expansion. A buffer's file is read to its
// declared byteLength at most (precheck() checked the two are equal), straight into tinygltf's vector (one copy in
// memory); any other file is an image, read only as far as its header says it needs (read_image_file).
struct FileAccess {
    std::string error;                                          // the last failure, for the message
    std::map<std::pair<uint64_t, uint64_t>, uint64_t> buffers;  // file_id -> declared byteLength
};
bool fs_exists(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}
std::string fs_expand(const std::string& path, void*) { return path; }
bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    try {
        FileAccess& access = *static_cast<FileAccess*>(user);
        const auto buffer = access.buffers.find(file_id(path));
        if (buffer != access.buffers.end()) {
            *out = read_regular_file_bytes(path, buffer->second, "a glTF buffer (.bin)");
        } else {
            const std::string bytes = read_image_file(path, "a glTF image");
            out->assign(bytes.begin(), bytes.end());
        }
        return true;
    } catch (const Error& e) {
        if (err) *err += e.what();
        static_cast<FileAccess*>(user)->error = e.what();
        return false;
    }
}
bool fs_write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

}  // namespace

void Loader::check_extensions() {
    for (const std::string& e : model.extensionsUsed)
        if (!supported_extension(e)) warn_once("ext " + e, "extension '" + e + "' is used but not supported; ignored");
}

namespace {

// The checks before tinygltf: the JSON's nesting depth and element counts (json_bounds.h), required extensions, each
// buffer's source and declared size (a missing file, a size that the file, data URI or BIN chunk does not hold), with
// JSON paths.
void precheck(const std::string_view json_text, const std::string& file, const std::string& dir, const Glb* glb,
              FileAccess& access) {
    check_json_bounds(json_text, file, gltf_json_bounds());  // before any parser recurses or allocates
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
    if (j.contains("scene")) {  // tinygltf 2.7 renders scene 0 for any index it cannot use
        const json& s = j["scene"];
        const size_t scenes = j.contains("scenes") && j["scenes"].is_array() ? j["scenes"].size() : 0;
        if (!s.is_number_unsigned() || s.get<uint64_t>() >= scenes)
            throw Error(file + ": /scene: " + s.dump().substr(0, 40) +
                        " is not a scene index; expected an integer in [0, " + str(scenes) + ")");
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
        if (declared == 0)  // (tinygltf 2.7 then indexes an empty vector: a raw vector::_M_range_check message)
            throw Error(file + ": " + at + "/byteLength: 0; a buffer holds at least one byte");
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
        access.buffers[file_id(path)] = declared;
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
    // An embedded image (a bufferView or data URI) decodes to at most max(2^24, 64 x its bytes) pixels: a 472 KB
    // file holding an 11000x11000 PNG decoded to 1.4 GB within the 135-MP budget of image files.
    int w = 0, h = 0;
    const uint64_t embedded_max = std::max<uint64_t>(uint64_t(1) << 24, uint64_t(64) * uint64_t(size));
    if (image->uri.empty() && image_header_size(bytes, size_t(size), w, h) &&
        uint64_t(w) * uint64_t(h) > embedded_max) {
        L.warnings.push_back(L.file + ": " + at + ": an embedded " + str(size_t(w)) + "x" + str(size_t(h)) +
                             " image in " + str(size_t(size)) + " bytes is over the budget of embedded images (" +
                             str(embedded_max) + " pixels: 64 a byte, at least 2^24); flat colour used");
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

Scene load(const std::string& file_bytes, const std::string& file) {
    std::string patched;  // compressed files made readable by tinygltf (core/load/gltf_compression.h)
    const std::string& bytes = compressed_json_fixups(file_bytes, file, patched) ? patched : file_bytes;
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
    FileAccess access;
    precheck(binary ? glb.json_text : std::string_view(bytes), file, dir, binary ? &glb : nullptr, access);

    Scene scene;
    scene.source = file;
    Loader L(file, scene);
    tinygltf::TinyGLTF gltf;
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
    decompress(L);
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
    scene.stats.dropped_nonfinite = L.dropped_nonfinite;
    scene.stats.dropped_degenerate = L.dropped_degenerate;
    // Per-triangle arrays all-absent are dropped (the scene then pays nothing for them).
    auto all_absent = [](const std::vector<uvec3>& v) {
        return std::all_of(v.begin(), v.end(), [](const uvec3& t) { return t.x == kNoIndex; });
    };
    if (all_absent(scene.normal_indices)) scene.normal_indices.clear(), scene.normals.clear();
    if (all_absent(scene.uv_indices)) scene.uv_indices.clear(), scene.uvs.clear();
    if (all_absent(scene.uv1_indices)) scene.uv1_indices.clear(), scene.uvs1.clear();
    if (all_absent(scene.color_indices)) scene.color_indices.clear(), scene.colors.clear();
    if (all_absent(scene.tangent_indices)) scene.tangent_indices.clear(), scene.tangents.clear();
    if (scene.triangles.empty()) scene.warnings.push_back(file + ": the scene has no triangles");
    L.convert_cameras();
    if (!scene.has_camera) scene.camera = scene.framing_camera();
    return scene;
}

}  // namespace
}  // namespace gltf_detail

bool is_gltf_path(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".gltf" || ext == ".glb";
}

Scene load_gltf(const std::string& path) {
    return gltf_detail::load(read_regular_file(path, gltf_detail::kMaxGltfBytes, "a glTF file"), path);
}

Scene load_gltf_from_memory(const std::string& bytes, const std::string& name) {
    return gltf_detail::load(bytes, name);
}

}  // namespace pv
