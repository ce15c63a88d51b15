// core/load/start_view.cpp: the start view of a scene without a camera.
//
// The rule. Candidate eyes are a 6x6x6 grid inside the scene's bounds (cell centres). From each, 96 probe rays go
// out in directions spread evenly over the sphere. A candidate is
//   - inside a solid when fewer than 60% of its hits are on front faces (counter-clockwise, as OBJ and glTF define
//     them): the inside of a closed object (a bunny, a sphere, a pillar) sees the backs of its surface, while a
//     room's walls face into it. Such candidates are left out;
//   - enclosed when every probe that goes sideways or down (up to 30 degrees above the horizon) hits a surface: an
//     atrium or a courtyard open to the sky is still enclosed, a box open at its side is not.
// The scene is an interior when at least a quarter of the candidates outside solids are enclosed (measured: Sponza
// 94%, the conference room 99%, Sibenik 41%; the Cornell boxes with their open fronts 2-7%, objects 0%). Then the
// eye is the enclosed candidate with the largest mean distance to what its probes hit (at least 5% of the bounds'
// diagonal: open space about it), looking along the horizontal direction whose free distance (to the first surface,
// or to the bounds where a ray escapes; averaged over +-11 degrees) is longest, +Y up, a 60-degree vertical field of
// view, the target half that free distance ahead (the viewer orbits about it). Otherwise (an object, an open box, a
// flat or empty scene, more than 2^24 triangles) the start view is the outside framing, Scene::framing_camera(),
// unchanged.
// load_scene (core/load/scene_file.cpp) uses the interior view only where light reaches it: a sealed one (every probe
// hits) in a scene without emitting surfaces or punctual lights is framed from outside instead, with a warning.
#include "core/load/start_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/render/accel.h"

namespace pv {
namespace {

constexpr int kGrid = 6;                    // candidate eyes per axis
constexpr int kProbes = 96;                 // probe directions per candidate
constexpr float kSkyY = 0.5f;               // probes with d.y above this (30 degrees up) do not count for closure
constexpr float kMinClosed = 0.99f;         // share of the counted probes that must hit (all of them)
constexpr float kMinFront = 0.6f;           // share of the hits that must be front faces
constexpr float kMinOpenness = 0.05f;       // mean hit distance over the bounds' diagonal
constexpr float kMinEnclosedShare = 0.25f;  // enclosed candidates over those outside solids
constexpr int kAzimuths = 64;               // horizontal directions tried for the view
constexpr int kAzimuthWindow = 2;           // free distances averaged over +-2 azimuths (+-11 degrees)
constexpr float kInteriorVfovDeg = 60.f;
constexpr size_t kMaxTriangles = size_t(1) << 24;

// Directions spread evenly over the sphere (a Fibonacci lattice), the same every time.
std::vector<vec3> sphere_directions(int n) {
    std::vector<vec3> d(static_cast<size_t>(n));
    const float golden = 3.14159265f * (3.f - std::sqrt(5.f));
    for (int k = 0; k < n; ++k) {
        const float y = 1.f - 2.f * (float(k) + 0.5f) / float(n);
        const float r = std::sqrt(std::max(0.f, 1.f - y * y));
        const float phi = golden * float(k);
        d[size_t(k)] = vec3(r * std::cos(phi), y, r * std::sin(phi));
    }
    return d;
}

// Distance from o (inside the box) along d to where it leaves the box [lo, hi].
float exit_distance(vec3 o, vec3 d, vec3 lo, vec3 hi) {
    float t = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (d[a] > 0.f) t = std::min(t, (hi[a] - o[a]) / d[a]);
        if (d[a] < 0.f) t = std::min(t, (lo[a] - o[a]) / d[a]);
    }
    return std::max(t, 0.f);
}

}  // namespace

StartView choose_start_view(const Scene& scene) {
    StartView out;
    out.camera = scene.framing_camera();
    if (scene.triangles.empty() || scene.triangles.size() > kMaxTriangles) return out;
    vec3 lo, hi;
    scene.bounds(lo, hi);
    const vec3 ext = hi - lo;
    const float diag = glm::length(ext);
    const float largest = std::max(ext.x, std::max(ext.y, ext.z));
    if (!(diag > 0.f) || !std::isfinite(diag) || std::min(ext.x, std::min(ext.y, ext.z)) < 1e-3f * largest) return out;

    ScopedFtzDaz ftz;
    const Accel accel(scene);
    const std::vector<vec3> dirs = sphere_directions(kProbes);
    int counted = 0;
    for (const vec3& d : dirs) counted += d.y <= kSkyY;

    // Per candidate: enclosed (an interior eye), free (not inside a solid: its hits are mostly front faces, or it
    // hits nothing).
    int enclosed = 0, in_free_space = 0;
    bool found = false;
    vec3 best_eye(0.f);
    float best_open = 0.f;
    for (int i = 0; i < kGrid; ++i)
        for (int j = 0; j < kGrid; ++j)
            for (int k = 0; k < kGrid; ++k) {
                const vec3 f((float(i) + 0.5f) / kGrid, (float(j) + 0.5f) / kGrid, (float(k) + 0.5f) / kGrid);
                const vec3 eye = lo + ext * f;
                int closed = 0, hits = 0, front = 0;
                double dist = 0.0;
                for (const vec3& d : dirs) {
                    Hit h;
                    if (!accel.intersect(Ray{eye, d}, h)) continue;
                    ++hits;
                    closed += d.y <= kSkyY;
                    dist += double(h.t);
                    const uvec3 t = scene.triangles[h.prim];
                    const vec3 ng = glm::cross(scene.positions[t.y] - scene.positions[t.x],
                                               scene.positions[t.z] - scene.positions[t.x]);
                    front += glm::dot(ng, d) < 0.f;
                }
                const float c = float(closed) / float(counted), fr = hits ? float(front) / float(hits) : 1.f;
                const float open = hits ? float(dist / hits) / diag : 0.f;
                if (fr < kMinFront) continue;  // inside a solid
                ++in_free_space;
                if (c < kMinClosed) continue;
                ++enclosed;
                if (open >= kMinOpenness && open > best_open) {
                    found = true;
                    best_open = open;
                    best_eye = eye;
                    out.closed = c;
                    out.front = fr;
                    out.openness = open;
                    out.sealed = hits == kProbes;
                }
            }
    out.enclosed_share = in_free_space ? float(enclosed) / float(in_free_space) : 0.f;
    if (out.enclosed_share < kMinEnclosedShare) found = false;
    if (!found) {
        out.sealed = false;
        return out;
    }

    // The view: the horizontal direction with the longest free distance (averaged over neighbouring azimuths).
    std::vector<float> free(kAzimuths);
    std::vector<vec3> az(kAzimuths);
    for (int a = 0; a < kAzimuths; ++a) {
        const float phi = 2.f * 3.14159265f * float(a) / float(kAzimuths);
        az[size_t(a)] = vec3(std::cos(phi), 0.f, std::sin(phi));
        Hit h;
        free[size_t(a)] =
            accel.intersect(Ray{best_eye, az[size_t(a)]}, h) ? h.t : exit_distance(best_eye, az[size_t(a)], lo, hi);
    }
    int best_a = 0;
    float best_free = -1.f;
    for (int a = 0; a < kAzimuths; ++a) {
        float sum = 0.f;
        for (int w = -kAzimuthWindow; w <= kAzimuthWindow; ++w) sum += free[size_t((a + w + kAzimuths) % kAzimuths)];
        if (sum > best_free) {
            best_free = sum;
            best_a = a;
        }
    }
    const float ahead = free[size_t(best_a)];
    out.inside = true;
    out.camera = CameraDesc{};
    out.camera.eye = best_eye;
    out.camera.target = best_eye + az[size_t(best_a)] * std::max(0.5f * ahead, 1e-3f * diag);
    out.camera.up = vec3(0.f, 1.f, 0.f);
    out.camera.vfov_deg = kInteriorVfovDeg;
    return out;
}

}  // namespace pv
