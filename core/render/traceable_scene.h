// core/render/traceable_scene.h: the scene prepared for tracing, in one object (after Tungsten's TraceableScene): the
// Scene, its current materials, the BVH, the emissive triangles, the environment, portals and sky guide. It answers
// closest hit, occlusion and the picker's queries, and is one light interface over all of its lights.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "core/render/accel.h"
#include "core/render/light_groups.h"
#include "core/render/lights.h"
#include "core/render/sky_guide.h"
#include "core/scene/camera.h"
#include "core/scene/environment.h"
#include "core/scene/scene.h"

// Lights: next-event estimation picks the environment with probability p_env (0 when it is black, 1 when there are
// no emissive triangles, else 1/2; the environment itself chooses between sky and sun) and otherwise a triangle by
// power (LightSet). sample_light's pdf, and light_pdf_hit / light_pdf_escape, include that selection probability,
// so a caller weighs a BSDF-sampled emitter against light sampling without knowing how the light was chosen.
//
// Portals (Scene::portals, the openings an interior is lit through; Cycles' portal lights, Bitterli et al. 2015):
// when there are any and the sky shines, the sky's share of an environment sample becomes a one-sample mixture:
// with probability kPortalProbability a point uniform by area over the portals (a portal picked by area),
// direction toward it, radiance eval() there, shadow ray to infinity as for any environment sample; otherwise the
// sky's own sampling. The sun keeps its share (sampling it less often doubled the sunlit room's error). The
// direction pdf is p_sun pdf_sun + (1 - p_sun) ((1 - q) pdf_sky + q sum over the portals the ray (ref, w) crosses
// of d^2 / (A_total |cos|)), so light_pdf_escape needs the ray's origin. The sky keeps its own sampling in the
// mixture: a portal that misses the opening costs variance, never bias. Without portals nothing changes (same
// draws, same pdfs, bit-identical images).
//
// Sky guide (core/render/sky_guide.h, set by the Renderer after its training pre-pass): the same mixture with the
// learned histogram in the portals' place (probability kSkyGuideProbability), when there are no portals. Without a
// guide nothing changes.
//
// Read-only and shared by all render threads; set_materials and set_environment are not concurrent with queries.

namespace pv {

// Details of the surface under a film position (for picking materials, re-targeting the orbit and focusing).
struct PickResult {
    uint32_t triangle = kNoIndex;
    uint32_t material = kNoIndex;
    float distance = 0.f;  // along the unit primary ray
    vec3 position{0.f};
};

class TraceableScene {
public:
    // Builds the BVH (throws pv::Error on failure; build_progress: see Accel), the light set and the environment
    // from the scene's own materials and environment settings. Embree builds on the calling thread's TBB arena.
    explicit TraceableScene(std::shared_ptr<const Scene> scene, const std::function<void(double)>& build_progress = {});
    ~TraceableScene();
    TraceableScene(const TraceableScene&) = delete;
    TraceableScene& operator=(const TraceableScene&) = delete;

    // Replaces the materials (same count as the scene's; ignored otherwise): the BVH is kept (its alpha filter sees
    // the edited cut-outs), the light set is rebuilt.
    void set_materials(const std::vector<Material>& materials);
    // Replaces the environment's parameters (sky colour, map rotation and strength, sun); the map is the scene's.
    void set_environment(const EnvironmentSettings& settings);
    // Replaces the global medium (the scene's fog at construction; the viewer edits it).
    void set_fog(const HomogeneousMedium& fog) {
        m_fog = fog;
        update_media();
    }

    const Scene& scene() const { return *m_scene; }
    const std::vector<Material>& materials() const { return m_materials; }
    const Material& material(uint32_t prim) const { return m_materials[m_scene->material_ids[prim]]; }
    // Triangle prim's packed hit record (scene.h: TriangleRecord), or null when the scene is too large to pack.
    const TriangleRecord* triangle_record(uint32_t prim) const { return m_records ? m_records.get() + prim : nullptr; }
    const Accel& accel() const { return *m_accel; }
    const LightSet& triangle_lights() const { return m_lights; }
    const Environment& environment() const { return m_environment; }
    const EnvironmentSettings& environment_settings() const { return m_environment_settings; }
    const HomogeneousMedium& fog() const { return m_fog; }
    // A medium anywhere: the fog or a material's interior medium (the walker's one flag test; docs/media.md).
    bool has_media() const { return m_has_media; }

    // Closest hit and occlusion (see Accel).
    bool intersect(const Ray& ray, Hit& hit) const { return m_accel->intersect(ray, hit); }
    bool occluded(const Ray& ray) const { return m_accel->occluded(ray); }
    // The surface seen through film position film_px (pixels) of `camera`, by its primary ray through the lens
    // centre; nothing when the ray leaves the scene.
    std::optional<PickResult> pick(const Camera& camera, vec2 film_px) const;

    // The light groups (core/render/light_groups.h), rebuilt with the materials and the environment.
    const LightGroups& light_groups() const { return m_groups; }

    // ---- Lights: emissive triangles, environment and sun as one.
    // True if light sampling can find any light.
    bool has_lights() const { return !m_lights.empty() || m_p_env > 0.f; }
    // True if sample_light uses u_select (false when the environment is the only light: callers skip that draw).
    // With portals the draw also chooses between the portals and the environment's own sampling.
    bool light_selection_draw() const { return m_p_env != 1.f || m_p_mix > 0.f; }
    // Samples a light direction from `ref` into `ls` (pdf per solid angle, the selection probability included; an
    // environment sample has dist = infinity). False (ls unspecified) when the sample is useless.
    // ref_n: the shading normal at ref (or 0), which the light tree's pick weighs the receiver's cosine with.
    // skip_unlit: see LightSet::sample (the path tracer drops samples of one-sided emitters seen from behind).
    bool sample_light(vec3 ref, vec3 ref_n, float u_select, vec2 u, LightSample& ls, bool skip_unlit = false) const;
    // The pdf sample_light would give point p (normal n) on emissive triangle `tri` from `ref` (normal ref_n).
    float light_pdf_hit(uint32_t tri, vec3 ref, vec3 ref_n, vec3 p, vec3 n) const {
        return (1.f - m_p_env) * m_lights.pdf(tri, ref, ref_n, p, n);
    }
    // How an emissive triangle is chosen (RenderSettings::light_sampler); kept across set_materials. Not
    // concurrent with queries.
    void set_light_sampler(LightSamplerKind kind) {
        m_light_sampler = kind;
        m_lights.set_sampler(kind);
    }
    LightSamplerKind light_sampler() const { return m_light_sampler; }
    // The pdf sample_light would give the environment in direction dir from `ref` (the ray's origin: portals make
    // it depend on where the ray starts).
    float light_pdf_escape(vec3 ref, vec3 dir) const {
        return m_environment.is_black() ? 0.f : escape_pdf(ref, dir, m_environment.pdf_sky(dir));
    }
    // Emission a ray finds: on a hit with material `mat` from the front (or not), emitted_at() when emits() (a
    // one-sided emitter is black behind); on leaving the scene in direction dir, emitted_escape(dir), nothing when
    // environment_black().
    static bool emits(const Material& mat, bool front) {
        return mat.has_emission() && (front || mat.two_sided_emission);
    }
    bool environment_black() const { return m_environment.is_black(); }
    vec3 emitted_escape(vec3 dir) const { return m_environment.eval(dir); }
    // emitted_escape(dir), and light_pdf_escape(ref, dir) in *light_pdf, the same values from one texel search (a
    // BSDF-sampled ray that leaves the scene needs both).
    vec3 emitted_escape_and_pdf(vec3 ref, vec3 dir, float* light_pdf) const;
    // Probability that sample_light picks the environment rather than a triangle.
    float environment_selection_probability() const { return m_p_env; }
    // Probability that a sample of the sky aims through a portal (0 without portals or with a black sky).
    static constexpr float kPortalProbability = 0.5f;
    float portal_probability() const { return m_p_portal; }
    // Solid-angle pdf of the portal sampling alone (a point uniform by area over all portals) toward dir (unit)
    // from ref: the sum over the portals the ray crosses of d^2 / (A_total |cos|); 0 without portals.
    float portal_pdf(vec3 ref, vec3 dir) const;
    // Samples that distribution: u_pick chooses the portal, u the point on it. False when degenerate.
    bool sample_portal(vec3 ref, float u_pick, vec2 u, vec3& wi) const;

    // The learned sky distribution mixed into the sky's sampling (nullptr: none). Not concurrent with queries.
    void set_sky_guide(std::shared_ptr<const SkyGuide> guide);
    const SkyGuide* sky_guide() const { return m_sky_guide.get(); }
    static constexpr float kSkyGuideProbability = 0.5f;
    // Probability that a sample of the sky follows the guide (0 without one, with portals, or with a black sky).
    float sky_guide_probability() const { return m_p_portal > 0.f ? 0.f : m_p_mix; }

private:
    void update_selection();
    void update_media();
    // The environment's sample when the sky's sampling is a mixture with portals or the guide (u_select in [0, 1):
    // the mixture's other part or the environment, then which portal or bin).
    bool sample_environment_mixed(vec3 ref, float u_select, vec2 u, LightSample& ls) const;
    // The environment's pdf toward dir from ref then (without the selection probability p_env), given the sky's own
    // pdf toward dir.
    float environment_pdf_mixed(vec3 ref, vec3 dir, float sky_pdf) const;
    // light_pdf_escape of a shining environment, given the sky's own pdf toward dir.
    float escape_pdf(vec3 ref, vec3 dir, float sky_pdf) const {
        if (m_p_mix == 0.f) return m_p_env * m_environment.pdf_given_sky(dir, sky_pdf);
        return m_p_env * environment_pdf_mixed(ref, dir, sky_pdf);
    }
    // The mixture's other part: the portals', else the guide's.
    float mix_pdf(vec3 ref, vec3 dir) const {
        return m_p_portal > 0.f ? portal_pdf(ref, dir) : m_sky_guide->pdf(ref, dir);
    }

    std::shared_ptr<const Scene> m_scene;
    std::vector<Material> m_materials;
    std::unique_ptr<Accel> m_accel;
    // pack_triangles(scene) in a region of their own (core/base/huge_pages.h: on huge pages from 1 MiB up, where a
    // hit's record read rarely waits for a page walk); null above kMaxPackedTriangles.
    std::shared_ptr<const TriangleRecord> m_records;
    LightSet m_lights;
    LightSamplerKind m_light_sampler = LightSamplerKind::Power;
    EnvironmentSettings m_environment_settings;
    HomogeneousMedium m_fog;
    bool m_has_media = false;
    Environment m_environment;
    float m_p_env = 0.f;
    float m_p_portal = 0.f;
    float m_p_mix = 0.f;  // share of the sky's samples taken by the portals (m_p_portal) or else the guide
    std::shared_ptr<const SkyGuide> m_sky_guide;
    LightGroups m_groups;
    std::vector<float> m_portal_cdf;  // the scene's portals' cumulative areas / total, last 1
    float m_portal_area = 0.f;        // total
};

// Inline: the path tracer's per-vertex call.
inline bool TraceableScene::sample_light(vec3 ref, vec3 ref_n, float u_select, vec2 u, LightSample& ls,
                                         bool skip_unlit) const {
    const float p_env = m_p_env;
    if (u_select < p_env) {
        if (m_p_mix > 0.f) return sample_environment_mixed(ref, u_select / p_env, u, ls);
        const std::optional<EnvironmentSample> es = m_environment.sample(u);
        if (!es) return false;
        ls.wi = es->wi;
        ls.le = es->le;
        ls.pdf = p_env * es->pdf;
        ls.dist = std::numeric_limits<float>::infinity();
        ls.group = kEnvironmentGroup;
        return true;
    }
    if (!m_lights.sample(ref, ref_n, (u_select - p_env) / (1.f - p_env), u, ls, skip_unlit)) return false;
    ls.pdf *= 1.f - p_env;
    return true;
}

}  // namespace pv
