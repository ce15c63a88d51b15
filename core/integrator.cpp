// core/integrator.cpp: the path tracer (see integrator.h). Structure after pbrt-v4's PathIntegrator::Li.
#include "core/integrator.h"

#include "core/surface.h"

namespace pv {
namespace {

// Power heuristic with beta = 2 (Veach 1997, sec. 9.2.4), written to stay finite for huge pdfs.
inline float power_heuristic(float pa, float pb) {
    if (!(pa > 0.f)) return 0.f;
    if (std::isinf(pa)) return 1.f;
    const float r = pb / pa;
    return 1.f / (1.f + r * r);
}

// Weight of emission found by a BSDF-sampled ray when next-event estimation is on. With MIS, the power heuristic.
// Without, light sampling alone counts an emitter, except one it can never pick (light pdf 0: an emitter whose
// share of the power rounds to a selection probability of 0, or an unsampleable one): there the BSDF sample is
// the only estimator, weight 1. The two weights of any direction still sum to 1, so both stay unbiased.
inline float bsdf_hit_weight(bool mis, float bsdf_pdf, float light_pdf) {
    if (mis) return power_heuristic(bsdf_pdf, light_pdf);
    return light_pdf > 0.f ? 0.f : 1.f;
}

}  // namespace

std::string RenderSettings::describe() const {
    return std::string("nee=") + (light_sampling ? "on" : "off") + " mis=" + (mis ? "on" : "off") +
           " rr=" + (russian_roulette ? "on" : "off") + " max_depth=" + std::to_string(max_depth) +
           " seed=" + std::to_string(seed) + " sampler=" + sampler_name(sampler) +
           (sky_guide == SkyGuideMode::On     ? " sky_guide=on"
            : sky_guide == SkyGuideMode::Auto ? " sky_guide=auto"
                                              : "");
}

namespace {

// kPacked: the hit data comes from the packed records (TriangleRecord), which the scene has; else from its indexed
// arrays. Two instantiations, so that neither carries the other's loads and branches per vertex.
template <bool kPacked>
vec3 trace_path_with(const TraceableScene& ts, const RenderSettings& settings, Ray ray, Sampler& sampler,
                     PathCounters& counters) {
    const Scene& scene = ts.scene();
    const bool nee = settings.light_sampling && ts.has_lights();
    const bool mis = nee && settings.mis;
    const bool select_draw = ts.light_selection_draw();  // false when the environment is the only light
    // The environment the only light, sampled without portals or guide (what !select_draw means): its sample does
    // not depend on the vertex, so it is drawn as soon as the ray has hit, while the hit triangle's record (just
    // prefetched) is still on its way from memory: about a hundred nanoseconds of arithmetic that the record's miss
    // would otherwise wait through. The Sobol sampler draws a dimension as a function of it alone, so drawing
    // u_light for a vertex that then takes no light sample (a delta BSDF) changes nothing else; the independent
    // sampler draws in stream order and keeps the draw where it was.
    const bool early_sky = nee && !select_draw && sampler.kind() == SamplerKind::Sobol;

    vec3 L(0.f), beta(1.f);
    bool specular_bounce = true;  // the camera "bounce" counts like a delta one: emission is always added
    float prev_pdf = 0.f;         // solid-angle pdf of the BSDF sample that produced `ray`
    vec3 prev_p(0.f);
    float eta_scale = 1.f;
    uint64_t rays = 0, shadow_rays = 0, vertices = 0;  // counted locally, stored once

    for (int depth = 0;; ++depth) {
        Hit hit;
        ++rays;
        if (!ts.intersect(ray, hit)) {
            // The environment: weighted against its own light sampling, as for emissive triangles.
            if (!ts.environment_black()) {
                const vec3 le = ts.emitted_escape(ray.d);
                if (!nee || specular_bounce)
                    L += beta * le;
                else
                    L += beta * le * bsdf_hit_weight(mis, prev_pdf, ts.light_pdf_escape(prev_p, ray.d));
            }
            break;
        }
        ++vertices;
        // The hit triangle's vertices, uvs and material from its packed record (one cache line) when there is one.
        const TriangleRecord* record = kPacked ? ts.triangle_record(hit.prim) : nullptr;
        prefetch_hit(scene, hit, record);
        uint32_t early_dim = 0;
        vec2 early_u(0.f);
        LightSample early_ls;
        bool early_found = false;
        const bool early = early_sky && depth < settings.max_depth;
        if (early) {
            early_dim = sampler.reserve(kBounceDims);
            early_u = sampler.get2d_at(early_dim + 1);
            early_found = ts.sample_light(vec3(0.f), 0.f, early_u, early_ls);  // the point is not used
        }
        SurfacePoint sf;
        if constexpr (kPacked)
            sf = surface_point(scene, hit, *record);
        else
            sf = surface_point(scene, hit);
        const Material& mat = kPacked ? ts.materials()[record->material()] : ts.material(hit.prim);
        const vec3 wo_world = -ray.d;
        const bool front = glm::dot(wo_world, sf.ng) > 0.f;

        // Emission found by the BSDF-sampled ray; with NEE it is weighted so it is never counted twice.
        if (TraceableScene::emits(mat, front)) {
            if (!nee || specular_bounce)
                L += beta * mat.emission;
            else
                L += beta * mat.emission *
                     bsdf_hit_weight(mis, prev_pdf, ts.light_pdf_hit(hit.prim, prev_p, sf.p, sf.ng));
        }
        if (depth >= settings.max_depth) break;

        // Only textured materials pay for the texture lookup and a local copy of the BSDF. The lookup waits until
        // the BSDF's value is needed (after the shadow ray is traced), its texels prefetched now: on large scenes
        // the texel load is a cache miss, which then overlaps Embree's traversal. Same values, same image.
        const Bsdf* bsdf = &mat.bsdf;
        std::optional<Bsdf> textured;
        const Texture* base_color =
            mat.base_color_texture != kNoIndex ? &scene.textures[mat.base_color_texture] : nullptr;
        TexelFootprint texels;  // where the lookup reads, found once by the prefetch
        if (base_color) {
            const vec2 uv = kPacked ? record->uv_at(hit.u, hit.v) : scene.uv_at(hit.prim, hit.u, hit.v);
            texels = base_color->prefetch(uv);
        }
        auto shade = [&]() -> const Bsdf& {
            if (base_color && !textured) {
                textured.emplace(mat.bsdf);
                set_base_color(*textured, vec3(base_color->lookup(texels)));
                bsdf = &*textured;
            }
            return *bsdf;
        };

        // Shading frame (core/surface.h).
        const auto [ng, ns] = shading_normals(sf, wo_world, front, mat.bsdf);
        const Frame frame(ns);
        const vec3 wo = frame.to_local(wo_world);

        // This bounce's dimensions: light selection (+0), light point (+1), lobe (+2), direction (+3), roulette (+4).
        const uint32_t dim = early ? early_dim : sampler.reserve(kBounceDims);
        // Ray origins off the surface on each side of it, computed once when first needed (the shadow ray and the
        // continuation usually leave on the same side).
        vec3 origin[2];
        bool have_origin[2] = {false, false};
        auto origin_toward = [&](vec3 w) -> vec3 {
            const int side = glm::dot(w, sf.ng) > 0.f ? 0 : 1;
            if (!have_origin[side]) {
                origin[side] = offset_ray_origin(sf.p, side == 0 ? sf.ng : -sf.ng, sf.p_error);
                have_origin[side] = true;
            }
            return origin[side];
        };

        // The bounce's draws, taken together so that their independent hash chains overlap; only those the
        // vertex uses (one-lobe BSDFs need no lobe draw, delta ones no light or direction draws), in dimension order.
        const bool do_nee = nee && !is_delta(*bsdf);
        const float u_light_select = do_nee && select_draw ? sampler.get1d_at(dim) : 0.f;
        const vec2 u_light = do_nee ? (early ? early_u : sampler.get2d_at(dim + 1)) : vec2(0.f);
        const bool one_lobe = std::holds_alternative<Lambertian>(*bsdf) || std::holds_alternative<Mirror>(*bsdf);
        const float u_lobe = one_lobe ? 0.5f : sampler.get1d_at(dim + 2);
        const vec2 u_bsdf = is_delta(*bsdf) ? vec2(0.5f) : sampler.get2d_at(dim + 3);  // delta lobes ignore it

        // Next-event estimation.
        if (do_nee) {
            // The environment or a triangle; the selection probability is in the pdf.
            LightSample ls = early_ls;
            if ((early ? early_found : ts.sample_light(sf.p, u_light_select, u_light, ls)) && !is_black(ls.le)) {
                const vec3 wi = frame.to_local(ls.wi);
                const float cos_gl = glm::dot(ls.wi, ng);
                const bool same_side = (cos_gl > 0.f) == (wi.z > 0.f);
                // An untextured BSDF is evaluated first (no shadow ray toward a black value), a textured one once
                // the shadow ray is traced: its traversal hides the load of the prefetched texels. Textures apply to
                // reflection-only lobes, black below the surface whatever the colour: no shadow ray there either.
                vec3 f = same_side && !base_color ? eval(*bsdf, wo, wi) : vec3(0.f);
                bool visible = false;
                if (same_side && (base_color ? reflects(wo, wi) : !is_black(f))) {
                    const Ray shadow = shadow_ray(origin_toward(ls.wi), ls);
                    ++shadow_rays;
                    visible = !ts.occluded(shadow);
                    if (visible && base_color) f = eval(shade(), wo, wi);
                }
                if (visible && !is_black(f)) {
                    // The power heuristic's weight over the light pdf, w / p_l = p_l / (p_l^2 + p_b^2): one
                    // division (power_heuristic's guards: an infinite p_l weighs 1 / p_l = 0).
                    const float pl = ls.pdf;
                    float w_over_pdf = 1.f / pl;
                    if (mis && !std::isinf(pl)) {
                        const float pb = pdf(*bsdf, wo, wi);
                        const float denom = pl * pl + pb * pb;
                        w_over_pdf = denom > 0.f && std::isfinite(denom) ? pl / denom : power_heuristic(pl, pb) / pl;
                    }
                    L += beta * f * (std::fabs(wi.z) * w_over_pdf) * ls.le;
                }
            }
        }

        // BSDF sampling for the next direction.
        auto bs = sample(shade(), wo, u_lobe, u_bsdf);
        if (!bs) break;
        vec3 wi_world = frame.to_world(bs->wi);
        float cos_g = glm::dot(wi_world, ng);
        if (((cos_g > 0.f) != (bs->wi.z > 0.f) || cos_g == 0.f) && is_delta(*bsdf) && ns != ng) {
            // A mirror or glass direction about the shading normal that crosses the facet on the wrong side (at a
            // smooth-shaded silhouette): the surface itself is the facet here, so take this sample about the
            // geometric normal. Each sample's weight stays the lobe's own (1 reflected, 1/eta^2 refracted), so
            // no energy is lost or gained, where ending the path darkened the rim (tests/test_glass_furnace.cpp).
            const Frame geometric(ng);
            bs = detail::sample_other(*bsdf, geometric.to_local(wo_world), u_lobe, u_bsdf);  // out of line: rare
            if (!bs) break;
            wi_world = geometric.to_world(bs->wi);
            cos_g = glm::dot(wi_world, ng);
        }
        if ((cos_g > 0.f) != (bs->wi.z > 0.f) || cos_g == 0.f) break;  // would leak through the surface
        beta *= bs->f * (std::fabs(bs->wi.z) / bs->pdf);
        if (!is_finite(beta) || is_black(beta)) break;
        specular_bounce = bs->is_delta;
        prev_pdf = bs->pdf;
        prev_p = sf.p;
        eta_scale *= sqr(bs->eta);  // 1 except across a refraction

        // Russian roulette (issue 13, measured in docs/convergence.md): a path whose throughput m = max(beta) x
        // eta_scale (pbrt-v4's: the radiance scaling of refraction removed) is at least kRouletteThroughput always
        // continues; below it, it continues with probability m / kRouletteThroughput and survivors are divided by
        // that, so the estimator stays unbiased and a surviving path's throughput is brought back to the threshold.
        // pbrt-v4's rule (threshold 1 from the second vertex) plays roulette at nearly every bounce, since any
        // surface that is not white leaves the throughput below 1; 0.5 measured best in efficiency 1/(relMSE x s)
        // over the Cornell box, the mirror-and-glass box, the sunlit room, Sponza and Sibenik.
        if (settings.russian_roulette && depth >= 1) {
            const float m = max_component(beta) * eta_scale;
            if (m < kRouletteThroughput) {
                const float p = m / kRouletteThroughput;
                if (sampler.get1d_at(dim + 4) >= p) break;
                beta /= p;
            }
        }

        ray.o = origin_toward(wi_world);
        ray.d = wi_world;
        ray.tmax = std::numeric_limits<float>::infinity();
    }
    counters.paths++;
    counters.rays += rays;
    counters.shadow_rays += shadow_rays;
    counters.vertices += vertices;
    return L;
}

}  // namespace

vec3 trace_path(const TraceableScene& ts, const RenderSettings& settings, Ray ray, Sampler& sampler,
                PathCounters& counters) {
    if (ts.triangle_record(0)) return trace_path_with<true>(ts, settings, ray, sampler, counters);
    return trace_path_with<false>(ts, settings, ray, sampler, counters);
}

}  // namespace pv
