// core/render/lights.h: emissive triangles as area lights: a triangle picked by power (an exact alias table) or by
// the light tree (core/render/light_tree.h), a point on it by solid angle near it and by area elsewhere, and the
// exact density of that rule for MIS.
#pragma once

#include <algorithm>
#include <vector>

#include "core/render/light_tree.h"
#include "core/render/settings.h"
#include "core/sampling/distribution.h"
#include "core/sampling/spherical_triangle.h"
#include "core/sampling/warp.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

// The rule: a triangle is chosen with probability proportional to its
// power (luminance(Le) * area, doubled when two-sided), quantised by an exact alias table (DiscreteDistribution:
// pmf() is the probability sample() picks it with). A point on it is then chosen uniformly in the solid angle it
// subtends at the shading point (core/sampling/spherical_triangle.h), pdf_w = pmf / solid_angle, where the point is
// within kSphericalNearRadii of the triangle and that solid angle lies in [kMinSphericalSolidAngle,
// kMaxSphericalSolidAngle]; elsewhere uniformly by area, pdf_w = pmf / area * d^2 / |cos_light|. pdf() applies the
// same rule to the same point, so the density MIS weighs a BSDF-found emitter with is exactly the rule's.
// An emitter with an alpha cut-out (map_d, or map_Kd's alpha) emits alpha * Le at each point, light-sampled or hit.
// An emitter with a glTF emissiveTexture emits Le x texel RGB at each point (core/render/shading.h's emitted_at); its
// power is luminance(Le x the texture's mean RGB) x area (any positive pmf is unbiased; the mean favours bright
// textures). Zero-area and non-emissive triangles are never chosen, nor are emitters whose share of the power is below
// about 2^-24 (their pmf is 0): the integrator leaves those to BSDF sampling, as it does any emitter of pdf 0.

namespace pv {

struct LightSample {
    vec3 p{0.f};        // point on the light
    vec3 p_error{0.f};  // bound on p's rounding error (barycentric_error), for offset_ray_origin
    vec3 n{0.f};        // its unit geometric normal (winding order)
    vec3 le{0.f};       // emitted radiance toward the shading point (0 from a one-sided back face)
    vec3 wi{0.f};       // unit direction from the shading point to p
    float dist = 0.f;
    float pdf = 0.f;    // per solid angle at the shading point
    uint8_t group = 0;  // the light group (core/render/light_groups.h) credited with its radiance
};

// The shadow ray of a light sample, from `origin` (the shading point already offset to the side ls.wi leaves by):
// toward a point on an emitter, the segment to that point offset off the emitter (t in [0, 1 - 1e-4) of the
// unnormalised segment, pbrt-v4's ShadowEpsilon); toward the environment (dist infinite), unbounded along ls.wi.
// The integrator and the benchmark's minimal kernel both build their shadow rays here.
[[gnu::always_inline]] inline Ray shadow_ray(vec3 origin, const LightSample& ls) {
    Ray shadow;
    shadow.o = origin;
    if (std::isinf(ls.dist)) {
        shadow.d = ls.wi;
    } else {
        const vec3 target = offset_ray_origin(ls.p, glm::dot(ls.wi, ls.n) < 0.f ? ls.n : -ls.n, ls.p_error);
        shadow.d = target - shadow.o;
        shadow.tmax = 1.f - 1e-4f;
    }
    return shadow;
}

// The solid angles (sr) between which an emitter triangle is sampled by solid angle (pbrt-v4's bounds), and the
// distance from its centre, in radii of its bounding sphere, beyond which it is sampled by area without computing
// its solid angle. Measured on the Cornell box (docs/light-sampling.md): within 5 radii (most of the box) the
// spherical rule cut relMSE per sample by 6% but cost 25% of the sample rate; within 2 radii it costs nothing
// measurable there, and next to an emitter, where the area rule's variance explodes, it more than halves it.
constexpr float kMinSphericalSolidAngle = 3e-4f;
constexpr float kMaxSphericalSolidAngle = 6.22f;
constexpr float kSphericalNearRadii = 2.f;

// The light a glTF punctual light (Scene::punctual_lights, KHR_lights_punctual) sends toward `ref`: out.wi (unit,
// toward the light), out.dist (infinite for a directional light), out.p and out.n for shadow_ray, and out.le the
// irradiance it gives a surface at `ref` facing it: intensity / d^2 times the range falloff and the spot's cone
// (point and spot), intensity (directional). A delta light: out.pdf = 1, no MIS (no BSDF sample can hit it). False
// when it sends nothing there.
bool sample_punctual(const PunctualLight& light, vec3 ref, LightSample& out);

// LightSamplerKind (--light-sampler) is in core/render/settings.h.

class LightSet {
public:
    LightSet() = default;
    // Builds the distribution over the emissive triangles of `scene` using `materials`; keeps pointers into
    // scene.textures. solid_angle = false samples every emitter by area (the earlier rule; for tests).
    LightSet(const Scene& scene, const std::vector<Material>& materials, bool solid_angle = true);

    bool empty() const { return m_tris.empty(); }
    size_t size() const { return m_tris.size(); }
    // Chooses how a triangle is picked (the tree is built on first use and kept). Not concurrent with queries.
    void set_sampler(LightSamplerKind kind);
    LightSamplerKind sampler() const { return m_use_tree ? LightSamplerKind::Tree : LightSamplerKind::Power; }
    const LightTree& tree() const { return m_tree; }
    // Samples a light point as seen from `ref` (shading normal ref_n, or 0: the tree's pick then ignores the
    // receiver's cosine) into `out`; false (out unspecified) when the sample is useless (d = 0, cos = 0). With
    // skip_unlit, also false, before any point is chosen, when the picked emitter is one-sided and ref is behind it
    // or in its plane: exactly the samples whose out.le would be black (the path tracer's choice; the chi-square
    // tests sample the whole density). Inline: this is the path tracer's per-vertex call.
    bool sample(vec3 ref, vec3 ref_n, float u_select, vec2 u, LightSample& out, bool skip_unlit = false) const;
    // Solid-angle pdf that sample() picks point p on triangle `tri` (normal n) from `ref` (normal ref_n).
    float pdf(uint32_t tri, vec3 ref, vec3 ref_n, vec3 p, vec3 n) const;
    // Probability of choosing triangle `tri` (0 for non-lights) by power (the power sampler's, wherever the point).
    float pmf(uint32_t tri) const {
        return tri < m_emitter_of.size() && m_emitter_of[tri] != kNoIndex ? m_emitters[m_emitter_of[tri]].pmf : 0.f;
    }
    // Probability that sample() chooses triangle `tri` from `ref` (normal ref_n) under the sampler in force.
    float pmf(uint32_t tri, vec3 ref, vec3 ref_n) const {
        if (tri >= m_emitter_of.size() || m_emitter_of[tri] == kNoIndex) return 0.f;
        return m_use_tree ? m_tree.pmf(m_emitter_of[tri], ref, ref_n) : m_emitters[m_emitter_of[tri]].pmf;
    }
    float total_power() const { return m_total_power; }
    // Tags each emitter with its material's light group (per material, core/render/light_groups.h), which sample()
    // reports in LightSample::group.
    void set_groups(const Scene& scene, const std::vector<uint8_t>& material_group);

private:
    std::vector<uint32_t> m_tris;   // emissive triangle indices
    DiscreteDistribution m_select;  // over m_tris, by power
    // Gathered once so that a sample or pdf chases no indices and normalises nothing: per emissive triangle its
    // vertices, unit normal, emission and selection probability.
    struct Emitter {
        vec3 p0, p1, p2, n, emission;
        vec3 centre;     // of the triangle's bounding sphere (the vertices' mean)
        float near2;     // squared distance from centre within which the solid-angle rule may apply
        float pmf;       // selection probability
        float pdf_area;  // pmf / area
        float inv_area;  // 1 / area (the tree's pdf_area is its pmf times this)
        float power;     // luminance(Le x emissive texture mean) x area, doubled when two-sided
        bool two_sided;
        uint32_t alpha = kNoIndex;     // into m_alpha for an emitter with an alpha cut-out
        uint32_t emissive = kNoIndex;  // into m_emissive for an emitter with an emissive texture
        uint8_t group = 0;             // light group (set_groups)
    };
    // An emitter's alpha texture and its corners' uvs.
    struct AlphaCut {
        const Texture* texture;
        vec2 uv0, uv1, uv2;
    };
    // An emitter's emissive texture, its uv rule (Material::emissive_uv) and its corners' uvs in that rule's set.
    struct EmissiveCut {
        const Texture* texture;
        UvTransform transform;
        vec2 uv0, uv1, uv2;
    };
    std::vector<Emitter> m_emitters;
    std::vector<AlphaCut> m_alpha;
    std::vector<EmissiveCut> m_emissive;
    // Whether ref sees emitter e under a solid angle the spherical rule samples (omega: that solid angle).
    bool spherical(const Emitter& e, vec3 ref, float& omega) const;

    std::vector<uint32_t> m_emitter_of;  // per scene triangle: its index in m_emitters, kNoIndex for non-lights
    float m_total_power = 0.f;
    bool m_solid_angle = true;
    bool m_use_tree = false;
    LightTree m_tree;  // over m_emitters, built by set_sampler(Tree)
};

inline bool LightSet::spherical(const Emitter& e, vec3 ref, float& omega) const {
    if (!m_solid_angle) return false;
    const vec3 to_centre = e.centre - ref;
    if (glm::dot(to_centre, to_centre) > e.near2) return false;
    omega = spherical_triangle_area(ref, e.p0, e.p1, e.p2);
    return omega > kMinSphericalSolidAngle && omega < kMaxSphericalSolidAngle;
}

inline bool LightSet::sample(vec3 ref, vec3 ref_n, float u_select, vec2 u, LightSample& ls, bool skip_unlit) const {
    const size_t n = m_tris.size();
    if (n == 0) return false;
    size_t k;
    float pmf;
    if (m_use_tree) [[unlikely]] {
        uint32_t kt;
        if (!m_tree.sample(ref, ref_n, u_select, &kt, &pmf)) return false;
        k = kt;
    } else {
        k = m_select.sample(u_select);
        pmf = m_emitters[k].pmf;
    }
    const Emitter& e = m_emitters[k];
    // A one-sided emitter seen from behind or edge-on sends nothing to ref (cos_l below would be <= 0 at every point
    // of it): no point is chosen, and the spherical rule's work is skipped (the Cornell box's ceiling beside its lamp).
    if (skip_unlit && !e.two_sided && !(glm::dot(ref - e.p0, e.n) > 0.f)) return false;
    float omega = 0.f;
    const bool by_solid_angle = spherical(e, ref, omega);
    vec2 b;
    if (by_solid_angle) {
        if (!sample_spherical_triangle(ref, e.p0, e.p1, e.p2, u, b)) return false;
    } else {
        b = square_to_triangle(u);
    }
    const float b0 = 1.f - b.x - b.y;
    ls.p = b0 * e.p0 + b.x * e.p1 + b.y * e.p2;
    ls.p_error = barycentric_error(e.p0, e.p1, e.p2, b0, b.x, b.y);
    ls.n = e.n;
    const vec3 d = ls.p - ref;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.f)) return false;
    ls.dist = std::sqrt(d2);
    ls.wi = d * (1.f / ls.dist);
    const float cos_l = -glm::dot(ls.n, ls.wi);
    if (cos_l == 0.f) return false;
    ls.le = (cos_l > 0.f || e.two_sided) ? e.emission : vec3(0.f);
    ls.group = e.group;
    if (e.alpha != kNoIndex) {
        // An alpha cut-out emits in proportion to its opacity: the expected emission a BSDF-sampled ray finds
        // there, since the stochastic alpha test (core/render/accel.cpp) keeps such a hit with probability alpha.
        const AlphaCut& a = m_alpha[e.alpha];
        ls.le *= glm::clamp(a.texture->lookup(b0 * a.uv0 + b.x * a.uv1 + b.y * a.uv2).w, 0.f, 1.f);
    }
    if (e.emissive != kNoIndex) {
        // The emissive texture at the point's uv, as a BSDF-sampled ray finds it there (Scene::texcoord's formula).
        const EmissiveCut& t = m_emissive[e.emissive];
        ls.le *= vec3(t.texture->lookup(t.transform.apply(Scene::interpolate_uv(t.uv0, t.uv1, t.uv2, b.x, b.y))));
    }
    const float pdf_area = m_use_tree ? pmf * e.inv_area : e.pdf_area;
    ls.pdf = by_solid_angle ? pmf / omega : pdf_area * d2 / std::fabs(cos_l);
    return ls.pdf > 0.f && std::isfinite(ls.pdf);
}

}  // namespace pv
