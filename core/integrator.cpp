// core/integrator.cpp: the path tracer (see integrator.h). Structure after pbrt-v4's PathIntegrator::Li.
#include "core/integrator.h"

namespace pv {
namespace {

// Power heuristic with beta = 2 (Veach 1997, sec. 9.2.4), written to stay finite for huge pdfs.
inline float power_heuristic(float pa, float pb) {
    if (!(pa > 0.f)) return 0.f;
    if (std::isinf(pa)) return 1.f;
    const float r = pb / pa;
    return 1.f / (1.f + r * r);
}

struct Surface {
    vec3 p;
    vec3 p_error; // bound on p's rounding error (barycentric_error), for offset_ray_origin
    vec3 ng;      // unit geometric normal from the winding order
    vec3 ns;      // unit shading normal, same side as ng
    float area;   // triangle area
};

inline Surface surface_at(const Scene& s, const Hit& hit) {
    const uvec3 t = s.triangles[hit.prim];
    const vec3 p0 = s.positions[t.x], p1 = s.positions[t.y], p2 = s.positions[t.z];
    const float b0 = 1.f - hit.u - hit.v;
    Surface sf;
    // Reconstruct p from barycentrics, not o + t d, whose error grows with t (Waechter and Binder 2019).
    sf.p = b0 * p0 + hit.u * p1 + hit.v * p2;
    sf.p_error = barycentric_error(p0, p1, p2, b0, hit.u, hit.v);
    const vec3 c = glm::cross(p1 - p0, p2 - p0);
    const float len = glm::length(c);
    sf.area = 0.5f * len;
    sf.ng = c / len;
    sf.ns = sf.ng;
    if (!s.normal_indices.empty()) {
        const uvec3 ni = s.normal_indices[hit.prim];
        if (ni.x != kNoIndex) {
            const vec3 n = b0 * s.normals[ni.x] + hit.u * s.normals[ni.y] + hit.v * s.normals[ni.z];
            const float l2 = glm::dot(n, n);
            // A zero or NaN interpolated normal falls back to the geometric one (pbrt-v4, Triangle).
            if (l2 > 1e-12f && std::isfinite(l2)) sf.ns = n / std::sqrt(l2);
            if (glm::dot(sf.ns, sf.ng) < 0.f) sf.ns = -sf.ns;
        }
    }
    return sf;
}

}  // namespace

std::string RenderSettings::describe() const {
    return std::string("nee=") + (light_sampling ? "on" : "off") + " mis=" + (mis ? "on" : "off") +
           " rr=" + (russian_roulette ? "on" : "off") + " max_depth=" + std::to_string(max_depth) +
           " seed=" + std::to_string(seed) + " sampler=" + sampler_name(sampler);
}

vec3 trace_path(const SceneView& view, const RenderSettings& settings, Ray ray, Sampler& sampler,
                PathCounters& counters) {
    const Scene& scene = *view.scene;
    const std::vector<Material>& materials = *view.materials;
    const LightSet& lights = *view.lights;
    const Environment& env = *view.environment;
    const float p_env = environment_selection_probability(view);
    const bool nee = settings.light_sampling && (!lights.empty() || p_env > 0.f);
    const bool mis = nee && settings.mis;

    vec3 L(0.f), beta(1.f);
    bool specular_bounce = true;  // the camera "bounce" counts like a delta one: emission is always added
    float prev_pdf = 0.f;         // solid-angle pdf of the BSDF sample that produced `ray`
    vec3 prev_p(0.f);
    float eta_scale = 1.f;
    counters.paths++;

    for (int depth = 0;; ++depth) {
        Hit hit;
        counters.rays++;
        if (!view.accel->intersect(ray, hit)) {
            // The environment: weighted against its own light sampling, as for emissive triangles.
            if (!env.is_black()) {
                const vec3 le = env.eval(ray.d);
                if (!nee || specular_bounce)
                    L += beta * le;
                else if (mis)
                    L += beta * le * power_heuristic(prev_pdf, p_env * env.pdf(ray.d));
            }
            break;
        }
        counters.vertices++;
        const Surface sf = surface_at(scene, hit);
        const Material& mat = materials[scene.material_ids[hit.prim]];
        // Only textured materials pay for the texture lookup and a local copy of the BSDF.
        Bsdf textured;
        const Bsdf* bsdf = &mat.bsdf;
        if (mat.base_color_texture != kNoIndex) {
            textured = mat.bsdf;
            set_base_color(textured, vec3(scene.textures[mat.base_color_texture].lookup(scene.uv_at(hit.prim, hit.u, hit.v))));
            bsdf = &textured;
        }
        const vec3 wo_world = -ray.d;
        const bool front = glm::dot(wo_world, sf.ng) > 0.f;

        // Emission found by the BSDF-sampled ray; with NEE it is weighted so it is never counted twice.
        if (mat.has_emission() && (front || mat.two_sided_emission)) {
            if (!nee || specular_bounce) {
                L += beta * mat.emission;
            } else if (mis) {
                const float light_pdf = (1.f - p_env) * lights.pdf(hit.prim, prev_p, sf.p, sf.ng);
                L += beta * mat.emission * power_heuristic(prev_pdf, light_pdf);
            }
        }
        if (depth >= settings.max_depth) break;

        // Shading frame. Reflection lobes see the side wo is on; the dielectric needs the true orientation.
        const bool is_glass = std::holds_alternative<Dielectric>(mat.bsdf);
        vec3 ng = sf.ng, ns = sf.ns;
        if (!is_glass && !front) {
            ng = -ng;
            ns = -ns;
        }
        // Veach's rule: a direction must be on the same side of both normals; where the shading normal
        // would make wo back-facing, shade with the geometric normal instead.
        if ((glm::dot(wo_world, ns) > 0.f) != (glm::dot(wo_world, ng) > 0.f)) ns = ng;
        const Frame frame(ns);
        const vec3 wo = frame.to_local(wo_world);

        // Fixed dimension budget per bounce: light (1+2), BSDF (1+2), roulette (1).
        const float u_light_select = sampler.get1d();
        const vec2 u_light = sampler.get2d();
        const float u_lobe = sampler.get1d();
        const vec2 u_bsdf = sampler.get2d();
        const float u_rr = sampler.get1d();

        // Next-event estimation.
        if (nee && !is_delta(*bsdf)) {
            // Choose the environment or a triangle; the selection probability folds into the pdf.
            std::optional<LightSample> ls;
            if (u_light_select < p_env) {
                if (auto es = env.sample(u_light)) {
                    ls.emplace();
                    ls->wi = es->wi;
                    ls->le = es->le;
                    ls->pdf = p_env * es->pdf;
                    ls->dist = std::numeric_limits<float>::infinity();
                }
            } else if (auto ts = lights.sample(sf.p, (u_light_select - p_env) / (1.f - p_env), u_light)) {
                ls = ts;
                ls->pdf *= 1.f - p_env;
            }
            if (ls && !is_black(ls->le)) {
                const vec3 wi = frame.to_local(ls->wi);
                const bool same_side = (glm::dot(ls->wi, ng) > 0.f) == (wi.z > 0.f);
                const vec3 f = same_side ? eval(*bsdf, wo, wi) : vec3(0.f);
                if (!is_black(f)) {
                    // Shadow ray between offset endpoints; t in [0, 1) of the unnormalised segment.
                    Ray shadow;
                    shadow.o = offset_ray_origin(sf.p, glm::dot(ls->wi, sf.ng) > 0.f ? sf.ng : -sf.ng, sf.p_error);
                    if (std::isinf(ls->dist)) {
                        shadow.d = ls->wi;  // toward the environment: unbounded
                    } else {
                        const vec3 target = offset_ray_origin(ls->p, glm::dot(ls->wi, ls->n) < 0.f ? ls->n : -ls->n, ls->p_error);
                        shadow.d = target - shadow.o;
                        shadow.tmax = 1.f - 1e-4f;  // pbrt-v4's ShadowEpsilon
                    }
                    counters.shadow_rays++;
                    if (!view.accel->occluded(shadow)) {
                        const float w = mis ? power_heuristic(ls->pdf, pdf(*bsdf, wo, wi)) : 1.f;
                        L += beta * f * std::fabs(wi.z) * ls->le * (w / ls->pdf);
                    }
                }
            }
        }

        // BSDF sampling for the next direction.
        const auto bs = sample(*bsdf, wo, u_lobe, u_bsdf);
        if (!bs) break;
        const vec3 wi_world = frame.to_world(bs->wi);
        const float cos_g = glm::dot(wi_world, ng);
        if ((cos_g > 0.f) != (bs->wi.z > 0.f) || cos_g == 0.f) break;  // would leak through the surface
        beta *= bs->f * (std::fabs(bs->wi.z) / bs->pdf);
        if (!is_finite(beta) || is_black(beta)) break;
        specular_bounce = bs->is_delta;
        prev_pdf = bs->pdf;
        prev_p = sf.p;
        eta_scale *= sqr(bs->eta);  // 1 except across a refraction

        // Russian roulette (pbrt-v4): after two bounces, continue with probability max(beta * eta_scale),
        // dividing survivors by it, so the estimator stays unbiased.
        if (settings.russian_roulette && depth >= 1) {
            const float m = max_component(beta) * eta_scale;
            if (m < 1.f) {
                const float q = glm::max(0.f, 1.f - m);
                if (u_rr < q) break;
                beta /= 1.f - q;
            }
        }

        ray.o = offset_ray_origin(sf.p, cos_g > 0.f ? ng : -ng, sf.p_error);
        ray.d = wi_world;
        ray.tmax = std::numeric_limits<float>::infinity();
    }
    return L;
}

}  // namespace pv
