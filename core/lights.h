// core/lights.h: emissive triangles as area lights. A triangle is chosen with probability proportional to its
// power (luminance(Le) * area, doubled when two-sided) and a point on it uniformly by area; the pdf is then
// converted to solid angle at the shading point: pdf_w = pdf_A * d^2 / |cos_light|.
// Zero-area and non-emissive triangles are never chosen.
#pragma once

#include "core/scene.h"

#include <optional>
#include <vector>

namespace pv {

struct LightSample {
    vec3 p{0.f};       // point on the light
    vec3 p_error{0.f}; // bound on p's rounding error (barycentric_error), for offset_ray_origin
    vec3 n{0.f};       // its unit geometric normal (winding order)
    vec3 le{0.f};      // emitted radiance toward the shading point (0 from a one-sided back face)
    vec3 wi{0.f};      // unit direction from the shading point to p
    float dist = 0.f;
    float pdf = 0.f;   // per solid angle at the shading point
};

class LightSet {
public:
    LightSet() = default;
    // Builds the distribution over the emissive triangles of `scene` using `materials`.
    LightSet(const Scene& scene, const std::vector<Material>& materials);

    bool empty() const { return m_tris.empty(); }
    size_t size() const { return m_tris.size(); }
    // Samples a light point as seen from `ref`. Nothing when the sample is useless (d = 0, cos = 0).
    std::optional<LightSample> sample(vec3 ref, float u_select, vec2 u) const;
    // Solid-angle pdf that sample() picks point p on triangle `tri` (normal n) from `ref`.
    float pdf(uint32_t tri, vec3 ref, vec3 p, vec3 n) const;
    // Probability of choosing triangle `tri` (0 for non-lights).
    float pmf(uint32_t tri) const { return tri < m_pmf.size() ? m_pmf[tri] : 0.f; }
    float total_power() const { return m_total_power; }

private:
    const Scene* m_scene = nullptr;
    const std::vector<Material>* m_materials = nullptr;
    std::vector<uint32_t> m_tris;   // emissive triangle indices
    std::vector<float> m_cdf;       // cumulative, normalised; size m_tris.size()
    std::vector<float> m_area;      // per emissive triangle
    std::vector<float> m_pmf;       // per scene triangle (empty when there are no lights)
    // Gathered once so that a sample or pdf chases no indices and normalises nothing: per emissive triangle its
    // vertices, unit normal and emission; per scene triangle pmf / area (0 for non-lights).
    struct Emitter {
        vec3 p0, p1, p2, n, emission;
        float pdf_area;  // pmf / area
        bool two_sided;
    };
    std::vector<Emitter> m_emitters;
    std::vector<float> m_pdf_area;
    float m_total_power = 0.f;
};

}  // namespace pv
