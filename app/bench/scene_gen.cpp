// app/bench/scene_gen.cpp: generated benchmark scenes (see scene_gen.h).
#include "app/bench/scene_gen.h"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "core/load/scene_file.h"

namespace pv {

void add_displaced_sphere(Scene& s, vec3 c, float r, float amp, int n_theta, int n_phi, uint32_t material) {
    const uint32_t base = static_cast<uint32_t>(s.positions.size());
    // Vertex rows from pole to pole; the poles are rows of coincident vertices (their triangles are dropped).
    for (int i = 0; i <= n_theta; ++i) {
        const float theta = kPi * float(i) / float(n_theta);
        for (int j = 0; j < n_phi; ++j) {
            const float phi = 2.f * kPi * float(j) / float(n_phi);
            const vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            const float bump =
                1.f + amp * std::sin(7.f * theta) * std::sin(9.f * phi) * std::sin(3.f * theta + 2.f * phi);
            s.positions.push_back(c + r * bump * d);
        }
    }
    auto at = [&](int i, int j) { return base + uint32_t(i * n_phi + (j % n_phi)); };
    const size_t before = s.triangles.size();
    for (int i = 0; i < n_theta; ++i)
        for (int j = 0; j < n_phi; ++j) {
            // Outward winding (counter-clockwise seen from outside).
            if (i > 0) s.triangles.push_back(uvec3(at(i, j), at(i, j + 1), at(i + 1, j)));
            if (i + 1 < n_theta) s.triangles.push_back(uvec3(at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)));
        }
    const size_t added = s.triangles.size() - before;
    s.material_ids.insert(s.material_ids.end(), added, material);
    if (!s.normal_indices.empty()) s.normal_indices.insert(s.normal_indices.end(), added, uvec3(kNoIndex));
    if (!s.uv_indices.empty()) s.uv_indices.insert(s.uv_indices.end(), added, uvec3(kNoIndex));
    if (!s.color_indices.empty()) s.color_indices.insert(s.color_indices.end(), added, uvec3(kNoIndex));
    if (!s.tangent_indices.empty()) s.tangent_indices.insert(s.tangent_indices.end(), added, uvec3(kNoIndex));
}

namespace {

template <class T>
size_t bytes_of(const std::vector<T>& v) {
    return v.size() * sizeof(T);
}

// The per-vertex and per-triangle arrays' bytes (what instancing multiplies; the BVH comes on top).
size_t geometry_bytes(const Scene& s) {
    return bytes_of(s.positions) + bytes_of(s.triangles) + bytes_of(s.normals) + bytes_of(s.normal_indices) +
           bytes_of(s.uvs) + bytes_of(s.uv_indices) + bytes_of(s.uvs1) + bytes_of(s.uv1_indices) + bytes_of(s.colors) +
           bytes_of(s.color_indices) + bytes_of(s.tangents) + bytes_of(s.tangent_indices) + bytes_of(s.material_ids);
}

}  // namespace

std::optional<Scene> generated_scene(const std::string& keyword) {
    if (keyword == "compressed-instanced") {
        // Shipped, made by scripts/make_compressed_showcase.sh; beside the built-in Cornell box.
        const std::filesystem::path box(builtin_scene_path());
        const std::string path = (box.parent_path().parent_path() / "compressed-instanced" / "scene.glb").string();
        const size_t file_bytes = size_t(std::filesystem::file_size(path));
        const auto t0 = std::chrono::steady_clock::now();
        Scene s = load_scene(path);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        rusage ru{};
        getrusage(RUSAGE_SELF, &ru);
        char text[320];
        std::snprintf(text, sizeof text,
                      "compressed-instanced (assets/compressed-instanced/scene.glb: %zu KB, meshopt + quantized, one "
                      "mesh placed by 400 nodes; loaded in %.0f ms, %zu triangles, %.1f MiB of geometry arrays, peak "
                      "RSS %.0f MiB after loading)",
                      file_bytes / 1024, ms, s.triangles.size(), double(geometry_bytes(s)) / 1048576.0,
                      double(ru.ru_maxrss) / 1024.0);
        s.source = text;
        std::fprintf(stderr, "pathview bench: %s\n", text);
        return s;
    }
    if (keyword == "many-lights") {
        // Shipped, made by scripts/make_many_lights.py; beside the built-in Cornell box.
        const std::filesystem::path box(builtin_scene_path());
        Scene s = load_scene((box.parent_path().parent_path() / "many-lights" / "scene.json").string());
        s.source = "many-lights (assets/many-lights: 320 lamps, 2560 emissive triangles)";
        return s;
    }
    if (keyword == "fog-box") {
        // Shipped, made by scripts/make_fog_box.py: the Cornell box in fog with a point lamp (docs/media.md).
        const std::filesystem::path box(builtin_scene_path());
        Scene s = load_scene((box.parent_path().parent_path() / "fog-box" / "scene.json").string());
        s.source = "fog-box (assets/fog-box: the Cornell box in fog, a point lamp inside)";
        return s;
    }
    if (keyword != "large-mesh") return std::nullopt;
    Scene s = load_scene(builtin_scene_path());
    Material white;
    white.name = "generated-sphere";
    white.bsdf = Lambertian{vec3(0.725f, 0.71f, 0.68f)};
    s.materials.push_back(white);
    add_displaced_sphere(s, vec3(278.f, 150.f, 280.f), 130.f, 0.06f, 512, 1024,
                         static_cast<uint32_t>(s.materials.size() - 1));
    s.source = "large-mesh (generated: Cornell box + displaced sphere)";
    return s;
}

}  // namespace pv
