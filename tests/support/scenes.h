// tests/support/scenes.h: scenes built in code for the analytic and statistical tests (spheres, boxes, quads),
// and two ways to render them: through the Renderer (as `pathview render` does) and sample by sample through
// trace_path with the Renderer's camera-sample convention, so a test can inspect every sample.
#pragma once

#include <functional>
#include <memory>

#include "core/image/film.h"
#include "core/render/integrator.h"
#include "core/render/traceable_scene.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace pv::test {

// Appends a material and returns its index.
uint32_t add_material(Scene& scene, const Material& m);
// Quad p0 p1 p2 p3 (counter-clockwise seen from the front): triangles (p0 p1 p2), (p0 p2 p3); normal cross(p1-p0,
// p2-p0).
void add_quad(Scene& scene, vec3 p0, vec3 p1, vec3 p2, vec3 p3, uint32_t material);
// Geodesic sphere: icosahedron subdivided `subdiv` times (20 * 4^subdiv triangles). Faces point outward, or
// inward when `inward` (an enclosure seen from inside).
void add_icosphere(Scene& scene, vec3 centre, float radius, int subdiv, uint32_t material, bool inward = false);
// Latitude-longitude sphere with nu segments around and nv rings; with `smooth`, per-vertex shading normals
// (the exact sphere normals), which makes a low-poly sphere's shading disagree with its facets.
void add_uv_sphere(Scene& scene, vec3 centre, float radius, int nu, int nv, uint32_t material, bool smooth);

// A scene prepared for tracing (the renderer's TraceableScene, from the scene's own materials and environment),
// with single-threaded sample-by-sample rendering on top.
class Tracer : public TraceableScene {
public:
    using TraceableScene::TraceableScene;

    // Calls fn(x, y, index, L) for `spp` samples of every pixel, single-threaded, with the Renderer's samples
    // (camera_ray, then trace_path) and floating-point mode (FTZ/DAZ). With pixel_centre the camera ray goes through
    // the pixel centre instead.
    void for_each_sample(const CameraDesc& camera, const RenderSettings& settings, int width, int height, int spp,
                         const std::function<void(int, int, uint32_t, vec3)>& fn, bool pixel_centre = false) const;
    // Accumulates for_each_sample into a Film (dropped samples counted into *dropped when given).
    Film render(const CameraDesc& camera, const RenderSettings& settings, int width, int height, int spp,
                bool pixel_centre = false, uint64_t* dropped = nullptr) const;
};

// Renders through the Renderer (threads workers, spp passes) and returns its film.
// Every pixel of `img` is finite and the image is not all black (a render smoke check).
void expect_finite_and_lit(const Image& img);

Film render_with_renderer(std::shared_ptr<const Scene> scene, const CameraDesc& camera, const RenderSettings& settings,
                          int width, int height, int spp, int threads = 2, uint64_t* dropped = nullptr);

// The environment's light samples from `ref` (sun, sky and any mixture with portals or a sky guide) follow
// light_pdf_escape (chi-square), each sample's own pdf is that value, and it integrates to 1 over the sphere.
void expect_environment_samples_follow_pdf(const TraceableScene& ts, vec3 ref);

// An open box (no ceiling) under a sky: a textured floor (an 8-bit checker with uvs), a mirror wall, a glossy wall, a
// glass ball and, with `emitter`, an emissive panel (then light sampling chooses between it and the sky; without it
// the sky is the only light and its sample is drawn at the hit). Every stage of the walker runs: textured and
// untextured hits, delta and non-delta BSDFs, escapes, emission found by BSDF sampling.
std::shared_ptr<Scene> open_box(bool emitter);

// The built-in Cornell box, loaded once per process.
std::shared_ptr<const Scene> cornell_box();

}  // namespace pv::test
