// core/scene/scene.h: the scene as plain data: one triangle mesh (positions, optional shading normals and UVs),
// a material per triangle, a camera description and the environment's settings (sky, map rotation and strength, sun).
// World units are whatever the OBJ uses. Triangles are validated on load (see obj_loader.h): every index is in
// range, every position finite, every triangle of non-zero area.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/base/math.h"
#include "core/scene/bsdf.h"
#include "core/scene/medium.h"
#include "core/scene/texture.h"

namespace pv {

// Pinhole or thin-lens camera. vfov in degrees; aperture is the lens radius (0 = pinhole);
// focus_distance 0 means "focus at the target".
struct CameraDesc {
    vec3 eye{0.f, 0.f, 5.f};
    vec3 target{0.f};
    vec3 up{0.f, 1.f, 0.f};
    float vfov_deg = 40.f;
    float aperture = 0.f;
    float focus_distance = 0.f;
};

// What loading dropped or assumed; reported once to the user.
struct LoadStats {
    size_t dropped_degenerate = 0;   // zero-area triangles
    size_t dropped_nonfinite = 0;    // triangles with a non-finite or absurd (> 1e18) vertex
    size_t dropped_overflow = 0;     // triangles whose area overflows float (edges near 1e18)
    size_t dropped_nontriangle = 0;  // faces tinyobjloader could not triangulate
    size_t default_material_tris = 0;
    size_t bad_normals = 0;  // corners whose normal was zero/NaN/missing: geometric normal used
};

// The environment's adjustable parameters (the map itself is Scene::environment_map): a constant sky radiance
// (when there is no map), the map's rotation and a strength multiplying the sky, and an optional sun: a disk of
// uniform radiance seen in `sun_direction` (toward the sun) with angular radius sun_angular_radius_deg, whose
// sun_irradiance is the irradiance it gives a surface facing it (off when black).
struct EnvironmentSettings {
    vec3 background{0.f};      // constant sky radiance when there is no map
    float rotation_deg = 0.f;  // map rotation about +y
    float strength = 1.f;      // multiplies the sky (map or background)
    vec3 sun_direction{0.f, 1.f, 0.f};
    float sun_angular_radius_deg = 0.27f;  // the real sun: 0.266 degrees
    vec3 sun_irradiance{0.f};

    bool operator==(const EnvironmentSettings& o) const {
        return background == o.background && rotation_deg == o.rotation_deg && strength == o.strength &&
               sun_direction == o.sun_direction && sun_angular_radius_deg == o.sun_angular_radius_deg &&
               sun_irradiance == o.sun_irradiance;
    }
    bool operator!=(const EnvironmentSettings& o) const { return !(*this == o); }
};

// A light portal: a parallelogram corner + s edge1 + t edge2 (s, t in [0, 1]) through which the environment lights
// an interior (a window's opening); next-event estimation aims half its environment samples through the portals
// (see traceable_scene.h). Geometry only: a portal neither blocks nor emits.
struct Portal {
    vec3 corner{0.f};
    vec3 edge1{0.f};
    vec3 edge2{0.f};
};

// A glTF KHR_lights_punctual light: a delta light, reached by next-event estimation only (no surface to hit).
// intensity is colour x intensity as the file gives it, taken directly in pathview's radiometric units (as three.js
// does): a point or spot light's radiant intensity (radiance x area, per steradian), so it gives the irradiance
// intensity x cos / d^2 at distance d; a directional light's irradiance on a surface facing it. range > 0 applies
// the extension's recommended falloff clamp(1 - (d / range)^4, 0, 1)^2 (times 1 / d^2); 0 is no range. A spot
// light's intensity is scaled by the extension's smooth step between the outer and inner cone angles.
struct PunctualLight {
    enum class Type : uint8_t { Point, Spot, Directional };
    Type type = Type::Point;
    vec3 position{0.f};              // world space (point, spot)
    vec3 direction{0.f, 0.f, -1.f};  // unit, world space: the way the light travels (spot, directional)
    vec3 intensity{1.f};
    float range = 0.f;
    float inner_cone_rad = 0.f;            // spot: full intensity within this angle of `direction`
    float outer_cone_rad = 0.7853981634f;  // spot: none beyond this one (glTF's default pi / 4)
    std::string name;
};

struct Scene {
    std::vector<vec3> positions;
    std::vector<uvec3> triangles;       // indices into positions
    std::vector<vec3> normals;          // unit shading normals (may be empty)
    std::vector<uvec3> normal_indices;  // per triangle, into normals; empty, or kNoIndex where absent
    std::vector<vec2> uvs;
    std::vector<uvec3> uv_indices;   // per triangle, into uvs; empty, or kNoIndex where absent
    std::vector<vec2> uvs1;          // a second texture-coordinate set (glTF TEXCOORD_1); usually empty
    std::vector<uvec3> uv1_indices;  // per triangle, into uvs1; empty, or kNoIndex where absent
    // Linear RGB vertex colours (glTF COLOR_0) multiplying the base colour; empty unless a file has non-white ones.
    std::vector<vec3> colors;
    std::vector<uvec3> color_indices;  // per triangle, into colors; empty, or kNoIndex where absent
    // World-space unit tangents with the bitangent's sign in w (glTF TANGENT: B = w cross(N, T)), for normal maps;
    // empty unless a file gives them to a normal-mapped primitive (else tangents come from the uvs per triangle).
    std::vector<vec4> tangents;
    std::vector<uvec3> tangent_indices;  // per triangle, into tangents; empty, or kNoIndex where absent
    std::vector<uint32_t> material_ids;  // per triangle, into materials
    std::vector<Material> materials;

    std::vector<Texture> textures;  // referenced by Material::base_color_texture / alpha_texture

    CameraDesc camera;
    // Equirectangular environment map (y up; see environment.h): index into textures.
    uint32_t environment_map = kNoIndex;
    // The sky's and sun's parameters (the sky is the map if any, else the constant background).
    EnvironmentSettings environment;
    // Light portals toward the environment ("portals" in the JSON); empty: the environment is sampled alone.
    std::vector<Portal> portals;
    // glTF KHR_lights_punctual lights, in world space (empty for OBJ scenes).
    std::vector<PunctualLight> punctual_lights;
    // The global medium (fog) filling every place outside closed transmissive solids, the camera inside it
    // (core/scene/medium.h); empty: none. Inside a solid its own Beer-Lambert absorption applies instead.
    HomogeneousMedium fog;
    bool has_camera = false;
    // Named camera views saved with the scene file ("bookmarks" in the JSON).
    struct Bookmark {
        std::string name;
        CameraDesc camera;
    };
    std::vector<Bookmark> bookmarks;

    std::string source;  // the file it came from, for messages
    LoadStats stats;
    std::vector<std::string> warnings;
    // Index in `warnings` of the "lit by the default sky" notice, when the loader added one: a later
    // --environment removes exactly that notice.
    std::optional<size_t> default_sky_warning;

    size_t triangle_count() const { return triangles.size(); }
    // Interpolated texture coordinates on triangle `prim` at barycentrics (u, v) of vertices 1 and 2; 0 if none.
    vec2 uv_at(uint32_t prim, float u, float v) const {
        if (uv_indices.empty()) return vec2(0.f);
        const uvec3 ti = uv_indices[prim];
        if (ti.x == kNoIndex) return vec2(0.f);
        return interpolate_uv(uvs[ti.x], uvs[ti.y], uvs[ti.z], u, v);
    }
    // The vertex colour on triangle `prim` at barycentrics (u, v), when it has one (color_indices[prim].x !=
    // kNoIndex). Written c0 + u (c1 - c0) + v (c2 - c0) so that a uniform colour interpolates to itself bit for bit.
    vec3 color_at(uint32_t prim, float u, float v) const {
        const uvec3 ti = color_indices[prim];
        const vec3 c0 = colors[ti.x];
        return c0 + u * (colors[ti.y] - c0) + v * (colors[ti.z] - c0);
    }
    // The texture coordinate a texture reference reads at barycentrics (u, v): set 0 or 1, then its transform.
    vec2 texcoord(uint32_t prim, float u, float v, const UvTransform& t) const {
        vec2 uv(0.f);
        if (t.set == 0) {
            uv = uv_at(prim, u, v);
        } else if (!uv1_indices.empty() && uv1_indices[prim].x != kNoIndex) {
            const uvec3 ti = uv1_indices[prim];
            uv = interpolate_uv(uvs1[ti.x], uvs1[ti.y], uvs1[ti.z], u, v);
        }
        return t.apply(uv);
    }
    // The uv at barycentrics (u, v) of vertices 1 and 2 between corner uvs a, b, c (one formula for every caller:
    // the packed records below give the same bits).
    static vec2 interpolate_uv(vec2 a, vec2 b, vec2 c, float u, float v) { return (1.f - u - v) * a + u * b + v * c; }
    // True if any triangle's material emits.
    bool has_emitters() const;
    // Appends a triangle with material `material` (tests and generated scenes).
    void add_triangle(vec3 a, vec3 b, vec3 c, uint32_t material);
    // Axis-aligned bounds of all vertices.
    void bounds(vec3& lo, vec3& hi) const;
    // A camera that frames the whole scene from +z, looking down -z.
    CameraDesc framing_camera(float vfov_deg = 40.f) const;
};

// One triangle's hit data in one 64-byte cache line: its three vertex positions, its three uvs and its material id,
// copied out of the Scene's indexed arrays (pack_triangles). A hit then waits for one cache miss where the indexed
// layout waits for two in a row (the index, then the vertices or uvs it points to), and the texel prefetch that needs
// the uv starts one miss earlier. Shading normals stay indexed (neither archive interior has any).
struct alignas(64) TriangleRecord {
    static constexpr uint32_t kNoUv = 1u << 31;  // in material_and_flags: the triangle has no uvs (uv_at gives 0)
    vec3 p[3];
    vec2 uv[3];
    uint32_t material_and_flags = 0;

    uint32_t material() const { return material_and_flags & ~kNoUv; }
    // Scene::uv_at's value for this triangle, bit for bit.
    vec2 uv_at(float u, float v) const {
        if (material_and_flags & kNoUv) return vec2(0.f);
        return Scene::interpolate_uv(uv[0], uv[1], uv[2], u, v);
    }
};
static_assert(sizeof(TriangleRecord) == 64, "one cache line a triangle");

// Above this many triangles no records are packed (64 MiB of them): a large mesh's memory budget
// (LargeMeshSlow.TwoMillionTrianglesInBoundedMemory, 160 B a triangle with the BVH) has no room for 64 more bytes a
// triangle, and the indexed arrays serve it as before.
constexpr size_t kMaxPackedTriangles = size_t(1) << 20;

// True if `s` is packed: at most max_triangles triangles and material ids below TriangleRecord::kNoUv.
bool packs_triangles(const Scene& s, size_t max_triangles = kMaxPackedTriangles);
// The record of triangle i of `s` (when packs_triangles(s)).
TriangleRecord pack_triangle(const Scene& s, size_t i);
// The records of every triangle of `s`, in triangle order; empty when !packs_triangles(s, max_triangles).
std::vector<TriangleRecord> pack_triangles(const Scene& s, size_t max_triangles = kMaxPackedTriangles);

// The built-in Cornell box (assets/cornell-box), loaded from the installed assets folder.
std::string builtin_scene_path();

}  // namespace pv
