// core/load/obj_loader.cpp: OBJ text pre-scan (line-accurate validation), tinyobjloader parse, and conversion into
// the validated Scene arrays.
#include "core/load/obj_loader.h"

#include <tiny_obj_loader.h>

#include <cerrno>
#include <charconv>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/scene/material_params.h"
#include "core/scene/texture_decode.h"

namespace pv {
namespace {

constexpr float kMaxCoordinate = 1.844e18f;  // Embree ignores primitives beyond this

struct PreScan {
    std::vector<uint8_t> bad_vertex;  // per position: non-finite, absurd or unparseable
    size_t first_bad_line = 0;
    std::string first_bad_text;
};

std::string_view trim_left(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    return s;
}

// Scans the OBJ text once for what tinyobjloader accepts silently: NaN/inf/garbage coordinates (parsed as 0 or
// inf), indices that wrap past 32 bits, out-of-range indices. Throws for index errors, with the line.
PreScan prescan(const std::string& text, const std::string& file) {
    PreScan ps;
    size_t line_no = 0, vcount = 0, vt_count = 0, vn_count = 0;
    size_t max_ref = 0, max_ref_line = 0;
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string_view line(text.data() + pos, end - pos);
        pos = end + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        line = trim_left(line);
        if (line.size() < 2) continue;
        if (line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
            // Position: three coordinates (an optional w is ignored). from_chars parses in place, no allocation.
            const char* p = line.data() + 2;
            const char* const line_end = line.data() + line.size();
            bool bad = false;
            for (int k = 0; k < 3; ++k) {
                while (p < line_end && (*p == ' ' || *p == '\t')) ++p;
                if (p < line_end && *p == '+') ++p;
                double x = 0.0;
                const auto r = std::from_chars(p, line_end, x);
                // Out of double's range: overflow is bad; underflow (1e-400) is a valid 0.
                bool overflow = false;
                if (r.ec == std::errc::result_out_of_range) {
                    const std::string_view token(p, size_t(r.ptr - p));
                    overflow = token.find("e-") == std::string_view::npos && token.find("E-") == std::string_view::npos;
                    x = 0.0;
                }
                if (r.ec == std::errc::invalid_argument || overflow || !std::isfinite(x) ||
                    std::fabs(x) > double(kMaxCoordinate))
                    bad = true;
                if (r.ptr == p) break;
                p = r.ptr;
            }
            ps.bad_vertex.push_back(bad ? 1 : 0);
            if (bad && ps.first_bad_line == 0) {
                ps.first_bad_line = line_no;
                ps.first_bad_text = std::string(line.substr(0, 60));
            }
            ++vcount;
        } else if (line[0] == 'v' && line[1] == 't') {
            ++vt_count;
        } else if (line[0] == 'v' && line[1] == 'n') {
            ++vn_count;
        } else if (line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) {
            const char* p = line.data() + 2;
            const char* const line_end = line.data() + line.size();
            while (p < line_end) {
                while (p < line_end && (*p == ' ' || *p == '\t')) ++p;
                if (p == line_end) break;
                long long idx = 0;
                const auto r = std::from_chars(p + (*p == '+' ? 1 : 0), line_end, idx);
                const char* e = r.ptr;
                if (r.ec == std::errc::invalid_argument) {
                    throw Error(file + ":" + std::to_string(line_no) + ": malformed face '" +
                                std::string(line.substr(0, 60)) + "'; expected vertex indices");
                }
                if (r.ec == std::errc::result_out_of_range || idx > INT_MAX || idx < -static_cast<long long>(INT_MAX)) {
                    while (e < line_end && *e >= '0' && *e <= '9') ++e;
                    throw Error(file + ":" + std::to_string(line_no) + ": face index " +
                                std::string(static_cast<const char*>(p), static_cast<const char*>(e)) +
                                " is out of range; expected an index between 1 and " + std::to_string(vcount));
                }
                if (idx == 0) {
                    throw Error(file + ":" + std::to_string(line_no) +
                                ": face index 0; OBJ indices start at 1 (or are negative, relative)");
                }
                if (idx < 0 && static_cast<long long>(vcount) + idx < 0) {
                    throw Error(file + ":" + std::to_string(line_no) + ": relative face index " + std::to_string(idx) +
                                " reaches before the first vertex; only " + std::to_string(vcount) +
                                " vertices precede it");
                }
                if (idx > 0 && static_cast<size_t>(idx) > max_ref) {
                    max_ref = static_cast<size_t>(idx);
                    max_ref_line = line_no;
                }
                p = e;
                while (p < line_end && *p != ' ' && *p != '\t') ++p;  // skip /vt/vn (validated after parsing)
            }
        }
    }
    if (max_ref > vcount) {
        throw Error(file + ":" + std::to_string(max_ref_line) + ": face references vertex " + std::to_string(max_ref) +
                    " but the file defines only " + std::to_string(vcount) + " vertices");
    }
    return ps;
}

vec3 to_vec3(const float* c) { return vec3(c[0], c[1], c[2]); }

// Forwards tinyobjloader's warnings, folding the ones that repeat per material ("Both `d` and `Tr`...", a known
// MTL quirk: d wins) into one line, and keeping at most 5 others.
void add_warnings(std::vector<std::string>& out, const std::string& file, const std::string& text) {
    std::istringstream in(text);
    std::string line;
    size_t d_and_tr = 0, kept = 0, skipped = 0;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        if (line.rfind("Both `d` and `Tr`", 0) == 0) {
            ++d_and_tr;
        } else if (kept < 5) {
            out.push_back(file + ": " + line);
            ++kept;
        } else {
            ++skipped;
        }
    }
    if (d_and_tr)
        out.push_back(file + ": " + std::to_string(d_and_tr) + " material(s) define both d and Tr; d is used");
    if (skipped) out.push_back(file + ": " + std::to_string(skipped) + " more loader warning(s) not shown");
}

// Reads a string in place as a std::istream (std::istringstream would copy it).
struct StringBuf : std::streambuf {
    explicit StringBuf(std::string& s) { setg(s.data(), s.data(), s.data() + s.size()); }
};

// Size limits of what the loader reads: far above real scenes (the largest OBJ in /work/shared/scenes is about
// 100 MB), low enough that a wrong file is refused instead of filling memory.
constexpr uint64_t kMaxObjBytes = uint64_t(8) << 30;
constexpr uint64_t kMaxMtlBytes = uint64_t(256) << 20;

// tinyobjloader's MaterialFileReader opens `mtllib` names with std::ifstream: a FIFO blocks it forever and
// /dev/zero grows memory without limit. This reader takes regular files only, up to kMaxMtlBytes.
class RegularMtlReader : public tinyobj::MaterialReader {
public:
    explicit RegularMtlReader(std::string dir) : m_dir(std::move(dir)) {}
    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* names, std::string* warn, std::string* err) override {
        std::string text;
        try {
            text = read_regular_file(m_dir + name, kMaxMtlBytes, "an MTL material library");
        } catch (const Error& e) {
            if (warn) *warn += std::string(e.what()) + "\n";
            return false;
        }
        StringBuf buf(text);
        std::istream in(&buf);
        tinyobj::LoadMtl(names, materials, &in, warn, err);
        return true;
    }

private:
    std::string m_dir;
};

// tinyobjloader's result.
struct ObjParse {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> mtls;
};

// Parses the (pre-scanned) text with tinyobjloader, reading `mtllib` files from mtl_dir (none if empty); forwards its
// warnings, and throws its error.
ObjParse parse_obj(std::string& text, const std::string& file, const std::string& mtl_dir,
                   std::vector<std::string>& warnings) {
    ObjParse parsed;
    std::string warn, err;
    StringBuf buf(text);
    std::istream in(&buf);
    RegularMtlReader reader(mtl_dir);
    const bool ok = tinyobj::LoadObj(&parsed.attrib, &parsed.shapes, &parsed.mtls, &warn, &err, &in,
                                     mtl_dir.empty() ? nullptr : &reader,
                                     /*triangulate=*/true, /*default_vcols_fallback=*/false);
    if (!ok) {
        std::string msg = err;
        while (!msg.empty() && (msg.back() == '\n' || msg.back() == '\r')) msg.pop_back();
        for (char& c : msg)
            if (c == '\n') c = ' ';
        throw Error(file + ": cannot parse OBJ: " + (msg.empty() ? "unknown error" : msg));
    }
    add_warnings(warnings, file, warn);
    if (!err.empty()) add_warnings(warnings, file, err);
    return parsed;
}

// Materials, and the textures they name (each file loaded once).
void add_materials(const std::vector<tinyobj::material_t>& mtls, const std::string& file, const std::string& mtl_dir,
                   const ObjOptions& options, Scene& scene) {
    std::map<std::string, uint32_t> texture_cache;
    auto texture = [&](const std::string& name, const std::string& material, bool alpha) -> uint32_t {
        if (name.empty()) return kNoIndex;
        const std::string found = mtl_dir.empty() ? std::string() : resolve_texture_path(mtl_dir, name);
        if (found.empty()) {
            scene.warnings.push_back(file + ": material '" + material + "': texture '" + name +
                                     "' not found (also tried ignoring letter case); flat colour used");
            return kNoIndex;
        }
        const std::string key = found + (alpha ? "#alpha" : "");
        if (auto it = texture_cache.find(key); it != texture_cache.end()) return it->second;
        try {
            scene.textures.push_back(Texture::load(found, alpha, &scene.warnings));
        } catch (const Error& e) {
            scene.warnings.push_back(std::string(e.what()) + "; flat colour used for material '" + material + "'");
            return kNoIndex;
        }
        const uint32_t id = static_cast<uint32_t>(scene.textures.size() - 1);
        texture_cache[key] = id;
        return id;
    };
    for (const auto& m : mtls) {
        Material mat = material_from_mtl(m.name, to_vec3(m.diffuse), to_vec3(m.specular), to_vec3(m.emission),
                                         m.shininess, m.ior, m.dissolve, m.illum, scene.warnings);
        mat.two_sided_emission = options.two_sided_emission;
        mat.base_color_texture = texture(m.diffuse_texname, m.name, false);
        if (!m.alpha_texname.empty()) {
            mat.alpha_texture = texture(m.alpha_texname, m.name, true);
        } else if (mat.base_color_texture != kNoIndex && scene.textures[mat.base_color_texture].has_alpha()) {
            mat.alpha_texture = mat.base_color_texture;  // map_Kd with an alpha channel cuts out too
        }
        scene.materials.push_back(std::move(mat));
    }
}

// Which vertex attributes are unusable: per position (non-finite or beyond kMaxCoordinate) and per normal (zero or
// non-finite length).
struct VertexFlags {
    std::vector<uint8_t> bad;
    std::vector<uint8_t> bad_n;
};

// Copies positions (zeroing the bad ones: their triangles are dropped by add_faces), unit normals and uvs.
VertexFlags add_vertices(const tinyobj::attrib_t& attrib, const PreScan& ps, Scene& scene) {
    VertexFlags flags;
    const size_t nv = attrib.vertices.size() / 3;
    scene.positions.resize(nv);
    flags.bad.assign(nv, 0);
    for (size_t i = 0; i < nv; ++i) {
        const vec3 p(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
        const bool b = (i < ps.bad_vertex.size() && ps.bad_vertex[i]) || !is_finite(p) ||
                       max_component(glm::abs(p)) > kMaxCoordinate;
        flags.bad[i] = b ? 1 : 0;
        scene.positions[i] = b ? vec3(0.f) : p;
    }
    // Normals: unit length, or marked unusable.
    const size_t nn = attrib.normals.size() / 3;
    scene.normals.resize(nn);
    flags.bad_n.assign(nn, 0);
    for (size_t i = 0; i < nn; ++i) {
        const vec3 n(attrib.normals[3 * i], attrib.normals[3 * i + 1], attrib.normals[3 * i + 2]);
        const float l2 = glm::dot(n, n);
        flags.bad_n[i] = (l2 > 1e-20f && std::isfinite(l2)) ? 0 : 1;
        scene.normals[i] = flags.bad_n[i] ? vec3(0.f, 0.f, 1.f) : n / std::sqrt(l2);
    }
    const size_t nt = attrib.texcoords.size() / 2;
    scene.uvs.resize(nt);
    for (size_t i = 0; i < nt; ++i) scene.uvs[i] = vec2(attrib.texcoords[2 * i], attrib.texcoords[2 * i + 1]);
    return flags;
}

// The shapes' triangles with their material, normal and uv indices; drops (and counts in scene.stats) non-triangles,
// triangles on bad vertices, overflowing and zero-area ones; faces without a known material get a default one.
void add_faces(const std::vector<tinyobj::shape_t>& shapes, const VertexFlags& flags, const std::string& file,
               Scene& scene) {
    const size_t nv = scene.positions.size(), nn = scene.normals.size(), nt = scene.uvs.size();
    const bool any_normals = nn > 0, any_uvs = nt > 0;
    uint32_t default_material = kNoIndex;

    size_t tri_total = 0;
    for (const auto& sh : shapes) tri_total += sh.mesh.num_face_vertices.size();
    scene.triangles.reserve(tri_total);
    scene.material_ids.reserve(tri_total);
    if (any_normals) scene.normal_indices.reserve(tri_total);
    if (any_uvs) scene.uv_indices.reserve(tri_total);

    for (const auto& sh : shapes) {
        size_t offset = 0;
        for (size_t f = 0; f < sh.mesh.num_face_vertices.size(); ++f) {
            const unsigned fv = sh.mesh.num_face_vertices[f];
            if (fv != 3) {
                scene.stats.dropped_nontriangle++;
                offset += fv;
                continue;
            }
            uvec3 vi, ni(kNoIndex), ti(kNoIndex);
            bool skip = false, normals_ok = any_normals, uvs_ok = any_uvs;
            for (int k = 0; k < 3; ++k) {
                const tinyobj::index_t& idx = sh.mesh.indices[offset + k];
                if (idx.vertex_index < 0 || static_cast<size_t>(idx.vertex_index) >= nv) {
                    throw Error(file + ": face in shape '" + sh.name + "' references vertex " +
                                std::to_string(idx.vertex_index + 1) + " of " + std::to_string(nv));
                }
                vi[k] = static_cast<uint32_t>(idx.vertex_index);
                if (flags.bad[vi[k]]) skip = true;
                if (idx.normal_index < 0 || static_cast<size_t>(idx.normal_index) >= nn ||
                    flags.bad_n[idx.normal_index])
                    normals_ok = false;
                else
                    ni[k] = static_cast<uint32_t>(idx.normal_index);
                if (idx.texcoord_index < 0 || static_cast<size_t>(idx.texcoord_index) >= nt)
                    uvs_ok = false;
                else
                    ti[k] = static_cast<uint32_t>(idx.texcoord_index);
            }
            offset += 3;
            if (skip) {
                scene.stats.dropped_nonfinite++;
                continue;
            }
            const vec3 p0 = scene.positions[vi.x], p1 = scene.positions[vi.y], p2 = scene.positions[vi.z];
            const float area2 = glm::length(glm::cross(p1 - p0, p2 - p0));
            if (!std::isfinite(area2)) {
                // Edges near 1e18 whose cross product overflows float: as unusable as a non-finite vertex.
                scene.stats.dropped_overflow++;
                continue;
            }
            if (!(area2 > 0.f)) {
                scene.stats.dropped_degenerate++;
                continue;
            }
            int mid = f < sh.mesh.material_ids.size() ? sh.mesh.material_ids[f] : -1;
            if (mid < 0 || static_cast<size_t>(mid) >= scene.materials.size()) {
                if (default_material == kNoIndex) {
                    default_material = static_cast<uint32_t>(scene.materials.size());
                    scene.materials.push_back(Material{});
                }
                scene.stats.default_material_tris++;
                mid = static_cast<int>(default_material);
            }
            scene.triangles.push_back(vi);
            scene.material_ids.push_back(static_cast<uint32_t>(mid));
            if (any_normals) {
                if (!normals_ok) scene.stats.bad_normals++;
                scene.normal_indices.push_back(normals_ok ? ni : uvec3(kNoIndex));
            }
            if (any_uvs) scene.uv_indices.push_back(uvs_ok ? ti : uvec3(kNoIndex));
        }
    }
}

// One warning per kind of dropped or repaired triangle counted in scene.stats.
void add_stats_warnings(const PreScan& ps, const std::string& file, Scene& scene) {
    const LoadStats& st = scene.stats;
    if (ps.first_bad_line) {
        scene.warnings.push_back(file + ":" + std::to_string(ps.first_bad_line) + ": vertex '" + ps.first_bad_text +
                                 "' is not finite or beyond 1e18; " + std::to_string(st.dropped_nonfinite) +
                                 " triangle(s) using such vertices dropped");
    } else if (st.dropped_nonfinite) {
        scene.warnings.push_back(file + ": " + std::to_string(st.dropped_nonfinite) +
                                 " triangle(s) with non-finite vertices dropped");
    }
    const std::pair<size_t, const char*> counted[] = {
        {st.dropped_overflow, " triangle(s) too large for float arithmetic (area overflows) dropped"},
        {st.dropped_degenerate, " zero-area triangle(s) dropped"},
        {st.dropped_nontriangle, " face(s) that could not be triangulated dropped"},
        {st.default_material_tris, " triangle(s) have no known material; default grey diffuse (0.8) used"},
        {st.bad_normals, " triangle(s) have missing or zero normals; geometric normals used"}};
    for (const auto& [count, what] : counted)
        if (count) scene.warnings.push_back(file + ": " + std::to_string(count) + what);
    if (scene.triangles.empty()) scene.warnings.push_back(file + ": the scene has no triangles");
}

// The stages: pre-scan (line-accurate errors), parse, materials and textures, vertices, faces, warnings.
Scene build_scene(std::string text, const std::string& file, const std::string& mtl_dir, const ObjOptions& options) {
    Scene scene;
    scene.source = file;
    // A UTF-8 byte-order mark would make tinyobjloader skip the first line.
    if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) {
        text.erase(0, 3);
        scene.warnings.push_back(file + ": UTF-8 byte-order mark ignored");
    }
    const PreScan ps = prescan(text, file);
    const ObjParse parsed = parse_obj(text, file, mtl_dir, scene.warnings);
    add_materials(parsed.mtls, file, mtl_dir, options, scene);
    const VertexFlags flags = add_vertices(parsed.attrib, ps, scene);
    add_faces(parsed.shapes, flags, file, scene);
    add_stats_warnings(ps, file, scene);
    if (scene.normals.empty()) scene.normal_indices.clear();
    if (scene.uvs.empty()) scene.uv_indices.clear();
    return scene;
}

}  // namespace

Material material_from_mtl(const std::string& name, vec3 kd, vec3 ks, vec3 ke, float ns, float ni, float d, int illum,
                           std::vector<std::string>& warnings) {
    Material m;
    m.name = name;
    m.emission = glm::max(ke, vec3(0.f));
    if (!is_finite(m.emission)) {
        warnings.push_back("material '" + name + "': Ke is not finite; it emits nothing");
        m.emission = vec3(0.f);
    }
    kd = glm::clamp(kd, vec3(0.f), vec3(1.f));
    ks = glm::clamp(ks, vec3(0.f), vec3(1.f));
    const bool dissolved = d < 1.f && d >= 0.f;
    if (dissolved && !(ni > 1.f) && !(illum == 4 || illum == 6 || illum == 7))
        warnings.push_back("material '" + name + "': d < 1 without Ni > 1 is not glass; rendered opaque");
    // The MTL model's choice of BSDF; the BSDF itself comes from make_bsdf, the one place that keeps its invariants.
    BsdfParams p;
    if (illum == 4 || illum == 6 || illum == 7 || (dissolved && ni > 1.f)) {
        if (!(ni > 1.f)) warnings.push_back("material '" + name + "': glass without Ni > 1; IOR 1.5 used");
        p.type = BsdfType::Glass;
        p.ior = ni > 1.f ? ni : 1.5f;
    } else if (illum == 3 || illum == 5) {
        p.type = BsdfType::Mirror;
        p.base = is_black(ks) ? vec3(1.f) : ks;
    } else if (!is_black(ks) && illum != 0 && illum != 1) {
        const float total = max_component(kd + ks);
        if (total > 1.f) {
            warnings.push_back("material '" + name + "': Kd + Ks exceeds 1; both scaled by " +
                               std::to_string(1.f / total) + " to conserve energy");
            kd /= total;
            ks /= total;
        }
        p.type = BsdfType::Glossy;
        p.base = kd;
        p.specular = ks;
        p.roughness = alpha_from_ns(ns);
    } else {
        p.type = BsdfType::Diffuse;
        p.base = kd;
    }
    m.bsdf = make_bsdf(p);
    return m;
}

Scene load_obj(const std::string& path, const ObjOptions& options) {
    std::string text = read_regular_file(path, kMaxObjBytes, "an OBJ scene");
    std::string dir = std::filesystem::path(path).parent_path().string();
    if (dir.empty()) dir = ".";
    return build_scene(std::move(text), path, dir + "/", options);
}

Scene load_obj_from_string(const std::string& text, const std::string& name, const ObjOptions& options) {
    return build_scene(text, name, "", options);
}

}  // namespace pv
