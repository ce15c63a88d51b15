// core/render/accel.h: ray-scene intersection through an Embree 3 BVH built from a Scene's triangles.
// Embree types stay in accel.cpp. Device errors become pv::Error. Thread-safe for concurrent queries.
#pragma once

#include <functional>
#include <memory>

#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace pv {

struct Hit {
    float t = 0.f;
    float u = 0.f, v = 0.f;    // barycentrics of vertices 1 and 2
    uint32_t prim = kNoIndex;  // triangle index in the Scene
};

struct AccelStats {
    double build_seconds = 0.0;
    size_t bytes = 0;  // BVH and geometry memory reported by Embree's memory monitor
};

class Accel {
public:
    // Builds the BVH. Throws pv::Error on an Embree device or build error. `progress`, when given, receives the
    // build's completed fraction in [0, 1] from Embree's build threads (it must be thread-safe). Alpha cut-outs
    // (Material::alpha_texture) come from `materials` (same count as the scene's), or the scene's own; triangles
    // whose material has none are a separate Embree geometry without the filter callback, so opaque surfaces pay
    // nothing for cut-outs elsewhere. The scene must outlive the Accel.
    explicit Accel(const Scene& scene, const std::function<void(double)>& progress = {});
    Accel(const Scene& scene, const std::vector<Material>& materials, const std::function<void(double)>& progress = {});
    ~Accel();
    // Edited materials (same count as the scene's; ignored otherwise): rays see their alpha cut-outs from now on.
    // Rebuilds the BVH only when the set of materials with a cut-out changes. Materials whose cut-outs are unchanged
    // change nothing here; a cut-out edit must not be concurrent with queries.
    void set_materials(const std::vector<Material>& materials);
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    // Closest hit with t in [FLT_MIN, ray.tmax] (a hit at t = 0, or one that flushed to 0, is the ray's own
    // surface); false if none. A ray Embree cannot take (a component of o or d beyond
    // +-1.844e18, or NaN) hits nothing.
    bool intersect(const Ray& ray, Hit& hit) const;
    // True if anything lies along the ray with t in [FLT_MIN, ray.tmax] (false for a ray Embree cannot take).
    bool occluded(const Ray& ray) const;
    const AccelStats& stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

// Sets flush-to-zero and denormals-are-zero on the calling thread (Embree's advice for tracing threads).
void enable_ftz_daz();

// FTZ/DAZ for a scope, then the thread's previous floating-point mode again: code that traces on a thread it does
// not own (tests, tools) runs in the renderer's mode without changing the caller's.
class ScopedFtzDaz {
public:
    ScopedFtzDaz();
    ~ScopedFtzDaz();
    ScopedFtzDaz(const ScopedFtzDaz&) = delete;
    ScopedFtzDaz& operator=(const ScopedFtzDaz&) = delete;

private:
    unsigned m_saved;
};

}  // namespace pv
