// core/load/gltf_meshes.cpp: the glTF loader's scene graph (see gltf_loader.h): the default scene's nodes with their
// world transforms, and the meshes (vertices and triangles, through core/load/gltf_internal.h's bounds-checked
// accessors) and KHR_lights_punctual lights they place. Files and parsing: core/load/gltf_loader.cpp; materials and
// cameras: core/load/gltf_materials.cpp.
#include <optional>

#include "core/load/gltf_internal.h"

namespace pv::gltf_detail {

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

namespace {

// v scaled to unit length, or nothing when its length is not finite or below 1e-20 (a normal or tangent that cannot
// be used: the caller substitutes a default and counts it).
std::optional<vec3> unit_or_none(dvec3 v) {
    const double l = glm::length(v);
    if (!(l > 1e-20) || !std::isfinite(l)) return std::nullopt;
    return vec3(v / l);
}

// A primitive's vertex attributes as the file gives them (TANGENT read only for a normal-mapped material).
struct PrimitiveAttributes {
    size_t nv = 0;  // vertices
    std::vector<float> pos, nrm, uv0, uv1, col, tan;
    int cc = 0;            // components per colour (3 or 4)
    bool colored = false;  // COLOR_0 present and not all white
};

// A primitive's attribute `name` (absent: empty), which must have the POSITION's count of elements.
std::vector<float> read_attribute(const Loader& L, const tinygltf::Primitive& prim, const std::string& at,
                                  const char* name, std::initializer_list<int> types, size_t nv, int& c) {
    const auto it = prim.attributes.find(name);
    if (it == prim.attributes.end()) return {};
    std::vector<float> v = L.read_floats(it->second, at + "/attributes/" + name, types, c);
    if (v.size() / size_t(c) != nv)
        L.fail(at + "/attributes/" + name,
               "count " + str(v.size() / size_t(c)) + " differs from POSITION's " + str(nv));
    return v;
}

PrimitiveAttributes read_attributes(const Loader& L, const tinygltf::Primitive& prim, const std::string& at,
                                    int position) {
    PrimitiveAttributes a;
    int comps = 0;
    a.pos = L.read_floats(position, at + "/attributes/POSITION", {TINYGLTF_TYPE_VEC3}, comps);
    a.nv = a.pos.size() / 3;
    int nc = 0, tc0 = 0, tc1 = 0;
    a.nrm = read_attribute(L, prim, at, "NORMAL", {TINYGLTF_TYPE_VEC3}, a.nv, nc);
    a.uv0 = read_attribute(L, prim, at, "TEXCOORD_0", {TINYGLTF_TYPE_VEC2}, a.nv, tc0);
    a.uv1 = read_attribute(L, prim, at, "TEXCOORD_1", {TINYGLTF_TYPE_VEC2}, a.nv, tc1);
    a.col = read_attribute(L, prim, at, "COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, a.nv, a.cc);
    // Only a primitive whose colours are not all white stores them (an all-white COLOR_0 multiplies by 1).
    for (size_t i = 0; i < a.col.size(); ++i)
        if ((a.cc == 3 || i % 4 != 3) && a.col[i] != 1.f) a.colored = true;
    return a;
}

// Triangles of the primitive (vertex numbers local to it), strips and fans as the specification orders them.
std::vector<uvec3> primitive_triangles(const std::vector<uint32_t>& idx, int mode) {
    std::vector<uvec3> tris;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        for (size_t i = 0; i + 2 < idx.size(); i += 3) tris.push_back(uvec3(idx[i], idx[i + 1], idx[i + 2]));
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < idx.size(); ++i)
            tris.push_back(i % 2 == 0 ? uvec3(idx[i], idx[i + 1], idx[i + 2]) : uvec3(idx[i + 1], idx[i], idx[i + 2]));
    } else {
        for (size_t i = 1; i + 1 < idx.size(); ++i) tris.push_back(uvec3(idx[i], idx[i + 1], idx[0]));
    }
    return tris;
}

// A mesh instance's transform: positions by `world`, normals by the inverse transpose, tangents by the linear part.
struct InstanceTransform {
    dmat4 world;
    dmat3 m3;
    dmat3 normal_matrix;
    bool flip;  // mirroring (negative determinant)
};

// Where a primitive's vertices start in the scene's arrays, and which of them are unusable.
struct PrimitiveVertices {
    uint32_t p0 = 0, n0 = 0, t0 = 0, t1 = 0, g0 = 0, c0 = 0;
    std::vector<uint8_t> bad, bad_n, bad_t;
    bool has_uv0 = false;
};

// Vertices: world positions, normals by the inverse transpose, uvs flipped to pathview's v-up convention (set 0
// through the base colour texture's transform), tangents (handedness w negated by a mirroring transform), colours.
PrimitiveVertices add_vertices(Scene& s, const PrimitiveAttributes& a, const InstanceTransform& xf,
                               const UvTransform& buv) {
    const size_t nv = a.nv;
    PrimitiveVertices v;
    v.p0 = uint32_t(s.positions.size());
    v.bad.assign(nv, 0);
    for (size_t i = 0; i < nv; ++i) {
        const vec3 p = vec3(xf.world * dvec4(a.pos[3 * i], a.pos[3 * i + 1], a.pos[3 * i + 2], 1.0));
        const bool b = !is_finite(p) || max_component(glm::abs(p)) > kMaxCoordinate;
        v.bad[i] = b;
        s.positions.push_back(b ? vec3(0.f) : p);
    }
    v.n0 = uint32_t(s.normals.size());
    v.bad_n.assign(a.nrm.empty() ? 0 : nv, 0);
    for (size_t i = 0; i < a.nrm.size() / 3; ++i) {
        const std::optional<vec3> n =
            unit_or_none(xf.normal_matrix * dvec3(a.nrm[3 * i], a.nrm[3 * i + 1], a.nrm[3 * i + 2]));
        v.bad_n[i] = !n;
        s.normals.push_back(n.value_or(vec3(0.f, 0.f, 1.f)));
    }
    const std::vector<float>& set0 = buv.set == 1 ? a.uv1 : a.uv0;
    v.has_uv0 = !set0.empty();
    v.t0 = uint32_t(s.uvs.size());
    v.t1 = uint32_t(s.uvs1.size());
    for (size_t i = 0; i < set0.size() / 2; ++i) {
        const vec2 uv = buv.apply(vec2(set0[2 * i], set0[2 * i + 1]));
        s.uvs.push_back(vec2(uv.x, 1.f - uv.y));
    }
    for (size_t i = 0; i < a.uv1.size() / 2; ++i) s.uvs1.push_back(vec2(a.uv1[2 * i], 1.f - a.uv1[2 * i + 1]));
    v.g0 = uint32_t(s.tangents.size());
    v.bad_t.assign(a.tan.empty() ? 0 : nv, 0);
    for (size_t i = 0; i < a.tan.size() / 4; ++i) {
        const std::optional<vec3> t = unit_or_none(xf.m3 * dvec3(a.tan[4 * i], a.tan[4 * i + 1], a.tan[4 * i + 2]));
        v.bad_t[i] = !t;
        const float w = (a.tan[4 * i + 3] < 0.f) != xf.flip ? -1.f : 1.f;
        s.tangents.push_back(t ? vec4(*t, w) : vec4(1.f, 0.f, 0.f, 1.f));
    }
    v.c0 = uint32_t(s.colors.size());
    if (a.colored)
        for (size_t i = 0; i < nv; ++i) {  // RGB (a VEC4's alpha is not used), clamped to [0, 1]
            const float* c = &a.col[size_t(a.cc) * i];
            s.colors.push_back(glm::clamp(vec3(finite_or(c[0], 1.f), finite_or(c[1], 1.f), finite_or(c[2], 1.f)),
                                          vec3(0.f), vec3(1.f)));
        }
    return v;
}

// The primitive's triangles and their attribute indices; those on bad vertices and zero-area ones are dropped (and
// counted in the loader).
void add_triangles(Loader& L, const std::vector<uvec3>& tris, const PrimitiveAttributes& a, const PrimitiveVertices& v,
                   uint32_t material, bool flip) {
    Scene& s = *L.scene;
    for (uvec3 t : tris) {
        if (v.bad[t.x] || v.bad[t.y] || v.bad[t.z]) {
            ++L.dropped_nonfinite;
            continue;
        }
        if (flip) std::swap(t.y, t.z);  // a mirroring transform turns counter-clockwise faces clockwise
        const vec3 pa = s.positions[v.p0 + t.x], pb = s.positions[v.p0 + t.y], pc = s.positions[v.p0 + t.z];
        const float area2 = glm::length(glm::cross(pb - pa, pc - pa));
        if (!(area2 > 0.f) || !std::isfinite(area2)) {
            ++L.dropped_degenerate;
            continue;
        }
        s.triangles.push_back(uvec3(v.p0) + t);
        s.material_ids.push_back(material);
        const bool normals_ok = !a.nrm.empty() && !v.bad_n[t.x] && !v.bad_n[t.y] && !v.bad_n[t.z];
        s.normal_indices.push_back(normals_ok ? uvec3(v.n0) + t : uvec3(kNoIndex));
        s.uv_indices.push_back(!v.has_uv0 ? uvec3(kNoIndex) : uvec3(v.t0) + t);
        s.uv1_indices.push_back(a.uv1.empty() ? uvec3(kNoIndex) : uvec3(v.t1) + t);
        s.color_indices.push_back(a.colored ? uvec3(v.c0) + t : uvec3(kNoIndex));
        const bool tangents_ok = !a.tan.empty() && !v.bad_t[t.x] && !v.bad_t[t.y] && !v.bad_t[t.z];
        s.tangent_indices.push_back(tangents_ok ? uvec3(v.g0) + t : uvec3(kNoIndex));
    }
}

}  // namespace

// Each primitive in turn: its attributes, indices and triangles (within the instancing budget), material, vertices
// (transformed into the scene's arrays), then its triangles.
void Loader::add_mesh(int mesh_index, const dmat4& world, const std::string& ref_at) {
    if (mesh_index < 0 || size_t(mesh_index) >= model.meshes.size())
        fail(ref_at,
             "mesh " + std::to_string(mesh_index) + " does not exist; the file has " + str(model.meshes.size()));
    Scene& s = *scene;
    const tinygltf::Mesh& mesh = model.meshes[size_t(mesh_index)];
    InstanceTransform xf;
    xf.world = world;
    xf.m3 = dmat3(world);
    xf.normal_matrix = glm::transpose(glm::inverse(xf.m3));
    xf.flip = glm::determinant(xf.m3) < 0.0;
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
        PrimitiveAttributes a = read_attributes(*this, prim, at, pos_it->second);
        const size_t nv = a.nv;
        std::vector<uint32_t> idx;
        if (prim.indices >= 0) {
            idx = read_indices(prim.indices, at + "/indices", nv);
        } else {
            idx.resize(nv);
            for (size_t i = 0; i < nv; ++i) idx[i] = uint32_t(i);
        }
        const std::vector<uvec3> tris = primitive_triangles(idx, mode);
        if (s.triangles.size() + tris.size() > budget || s.positions.size() + nv > budget)
            fail(at, "the scene would exceed " + str(budget) + " vertices or triangles (a mesh instanced by " +
                         str(visits) + " node visits; the limit is 16 per byte of the file's buffers, at least 2^22)");

        const uint32_t material = material_index(prim.material, at + "/material");
        const UvTransform& buv = prim.material >= 0 && size_t(prim.material) < base_uv.size()
                                     ? base_uv[size_t(prim.material)]
                                     : UvTransform{};
        // Tangents (glTF TANGENT) only for a normal-mapped material.
        const bool normal_mapped = material < s.materials.size() && s.materials[material].normal_texture != kNoIndex;
        int tgc = 0;
        if (normal_mapped) a.tan = read_attribute(*this, prim, at, "TANGENT", {TINYGLTF_TYPE_VEC4}, nv, tgc);
        const PrimitiveVertices v = add_vertices(s, a, xf, buv);
        add_triangles(*this, tris, a, v, material, xf.flip);
    }
}

}  // namespace pv::gltf_detail
