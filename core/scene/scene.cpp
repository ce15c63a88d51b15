// core/scene/scene.cpp: small helpers on Scene.
#include "core/scene/scene.h"

#include <algorithm>
#include <filesystem>

namespace pv {

void Scene::add_triangle(vec3 a, vec3 b, vec3 c, uint32_t material) {
    const uint32_t base = static_cast<uint32_t>(positions.size());
    positions.insert(positions.end(), {a, b, c});
    triangles.push_back(uvec3(base, base + 1, base + 2));
    material_ids.push_back(material);
    if (!normal_indices.empty()) normal_indices.push_back(uvec3(kNoIndex));
    if (!uv_indices.empty()) uv_indices.push_back(uvec3(kNoIndex));
    if (!uv1_indices.empty()) uv1_indices.push_back(uvec3(kNoIndex));
    if (!color_indices.empty()) color_indices.push_back(uvec3(kNoIndex));
    if (!tangent_indices.empty()) tangent_indices.push_back(uvec3(kNoIndex));
}

bool packs_triangles(const Scene& s, size_t max_triangles) {
    return s.triangle_count() <= max_triangles && s.materials.size() < TriangleRecord::kNoUv;
}

TriangleRecord pack_triangle(const Scene& s, size_t i) {
    TriangleRecord r;
    const uvec3 t = s.triangles[i];
    r.p[0] = s.positions[t.x];
    r.p[1] = s.positions[t.y];
    r.p[2] = s.positions[t.z];
    const uvec3 ti = s.uv_indices.empty() ? uvec3(kNoIndex) : s.uv_indices[i];
    r.material_and_flags = s.material_ids[i];
    if (ti.x == kNoIndex) {
        r.uv[0] = r.uv[1] = r.uv[2] = vec2(0.f);
        r.material_and_flags |= TriangleRecord::kNoUv;
    } else {
        r.uv[0] = s.uvs[ti.x];
        r.uv[1] = s.uvs[ti.y];
        r.uv[2] = s.uvs[ti.z];
    }
    return r;
}

std::vector<TriangleRecord> pack_triangles(const Scene& s, size_t max_triangles) {
    if (!packs_triangles(s, max_triangles)) return {};
    std::vector<TriangleRecord> records(s.triangle_count());
    for (size_t i = 0; i < records.size(); ++i) records[i] = pack_triangle(s, i);
    return records;
}

bool Scene::has_emitters() const {
    std::vector<uint8_t> used(materials.size(), 0);
    for (uint32_t m : material_ids) used[m] = 1;
    for (size_t i = 0; i < materials.size(); ++i)
        if (used[i] && materials[i].has_emission()) return true;
    return false;
}

void Scene::bounds(vec3& lo, vec3& hi) const {
    lo = vec3(std::numeric_limits<float>::max());
    hi = -lo;
    for (const uvec3& t : triangles)
        for (int k = 0; k < 3; ++k) {
            lo = glm::min(lo, positions[t[k]]);
            hi = glm::max(hi, positions[t[k]]);
        }
    if (triangles.empty()) lo = hi = vec3(0.f);
}

CameraDesc Scene::framing_camera(float vfov_deg) const {
    vec3 lo, hi;
    bounds(lo, hi);
    CameraDesc c;
    c.vfov_deg = vfov_deg;
    c.target = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    const float dist = radius / std::sin(0.5f * glm::radians(vfov_deg)) * 1.05f;
    c.eye = c.target + vec3(0.f, 0.15f * radius, dist);
    return c;
}

std::string builtin_scene_path() {
    // Next to the executable's source tree at build time; PATHVIEW_ASSETS overrides.
    if (const char* env = std::getenv("PATHVIEW_ASSETS")) return std::string(env) + "/cornell-box/scene.json";
    return std::string(PATHVIEW_ASSET_DIR) + "/cornell-box/scene.json";
}

}  // namespace pv
