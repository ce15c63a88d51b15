// core/render/integrator.cpp: the path tracer (see integrator.h). Structure after pbrt-v4's PathIntegrator::Li.
#include "core/render/integrator.h"

#include "core/render/shading.h"

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

void PathWalker::start(const TraceableScene& ts, const RenderSettings& settings, Ray ray, Sampler& sampler) {
    m_ts = &ts;
    m_settings = &settings;
    m_sampler = &sampler;
    m_observer = nullptr;
    m_groups = nullptr;
    // The hit data from the packed records (TriangleRecord) when the scene has them, else from its indexed arrays:
    // two instantiations, so that neither carries the other's loads and branches per vertex.
    m_step = ts.triangle_record(0) ? &PathWalker::step_with<true> : &PathWalker::step_with<false>;
    m_stage = Stage::Trace;
    m_nee = settings.light_sampling && ts.has_lights();
    m_mis = m_nee && settings.mis;
    m_select_draw = ts.light_selection_draw();  // false when the environment is the only light
    // The environment the only light, sampled without portals or guide (what !select_draw means): its sample does
    // not depend on the vertex, so it is drawn as soon as the ray has hit, while the hit triangle's record (just
    // prefetched) is still on its way from memory. The Sobol sampler draws a dimension as a function of it alone, so
    // drawing u_light for a vertex that then takes no light sample (a delta BSDF) changes nothing else; the
    // independent sampler draws in stream order and keeps the draw where it was.
    m_media = ts.has_media();
    m_medium = ts.fog().empty() ? nullptr : &ts.fog();
    m_equiangular = false;
    if (m_media && settings.light_sampling) [[unlikely]]
        for (const PunctualLight& l : ts.scene().punctual_lights)
            m_equiangular |= l.type != PunctualLight::Type::Directional;
    m_nesting = 0;
    m_early_sky = m_nee && !m_select_draw && sampler.kind() == SamplerKind::Sobol && !m_media;
    m_ray = ray;
    m_L = vec3(0.f);
    m_beta = vec3(1.f);
    m_specular_bounce = true;  // the camera "bounce" counts like a delta one: emission is always added
    m_prev_pdf = 0.f;
    m_prev_p = vec3(0.f);
    m_prev_n = vec3(0.f);
    m_eta_scale = 1.f;
    m_absorbing = false;
    m_depth = 0;
    m_counters = PathCounters{};
}

// One vertex is three stages: Trace (the closest hit, then the hit record's prefetch: wait), Surface (the surface
// point, emission found, the texels' prefetch: wait, when textured) and Scatter (light sample and shadow ray, BSDF
// sample, roulette, the next ray), which goes on to the next vertex's Trace without waiting. Each stage is a function
// of its own, as are Scatter's parts (next_event, punctual_lights, continue_path, roulette); all are inlined here
// (PV_STAGE), so the hot loop is the one function it was.
#define PV_STAGE [[gnu::always_inline]] inline

template <bool kPacked>
bool PathWalker::step_with() {
    for (;;) {
        switch (m_stage) {
            case Stage::Trace:
                if (trace<kPacked>() == Next::End) return finish();
                return true;  // the record is on its way
            case Stage::Surface: {
                const Next next = surface<kPacked>();
                if (next == Next::End) return finish();
                if (next == Next::Wait) return true;  // the texels are on their way
                [[fallthrough]];
            }
            case Stage::Scatter:
                if (scatter() == Next::End) return finish();
                break;  // on to the next vertex's closest hit
        }
    }
}

// The closest hit (or the escape to the environment), the hit record's prefetch and, with m_early_sky, the
// environment's light sample.
template <bool kPacked>
PV_STAGE PathWalker::Next PathWalker::trace() {
    const TraceableScene& ts = *m_ts;
    Hit& hit = m_hit;
    ++m_counters.rays;
    const bool found = ts.intersect(m_ray, hit);
    if (m_medium) [[unlikely]] {
        Next next;
        if (medium_segment(found, found ? hit.t : std::numeric_limits<float>::infinity(), next)) return next;
    }
    if (!found) {
        escape();
        return Next::End;
    }
    ++m_counters.vertices;
    if (m_absorbing) [[unlikely]]
        m_beta *= glm::exp(-m_sigma * hit.t);  // Beer-Lambert inside a solid (m_ray.d is a unit vector)
    // The hit triangle's vertices, uvs and material from its packed record (one cache line) when there is one.
    m_record = kPacked ? ts.triangle_record(hit.prim) : nullptr;
    prefetch_hit(ts.scene(), hit, m_record);
    m_early = m_early_sky && m_depth < m_settings->max_depth;
    m_early_found = false;
    if (m_early) {
        m_early_dim = m_sampler->reserve(kBounceDims);
        m_early_u = m_sampler->get2d_at(m_early_dim + 1);
        m_early_found = ts.sample_light(vec3(0.f), vec3(0.f), 0.f, m_early_u, m_early_ls);  // the point is not used
    }
    m_stage = Stage::Surface;
    return Next::Wait;
}

// The environment seen by the escaping ray: weighted against its own light sampling, as for emissive triangles.
PV_STAGE void PathWalker::escape() {
    const TraceableScene& ts = *m_ts;
    if (ts.environment_black()) return;
    if (!m_nee || m_specular_bounce) {
        add(m_beta * ts.emitted_escape(m_ray.d), kEnvironmentGroup, m_ray.d);
    } else {
        float light_pdf = 0.f;
        const vec3 le = ts.emitted_escape_and_pdf(m_prev_p, m_ray.d, &light_pdf);
        add(m_beta * le * bsdf_hit_weight(m_mis, m_prev_pdf, light_pdf), kEnvironmentGroup, m_ray.d);
    }
}

// The surface point and material, emission found, and the texture lookup's prefetch (Wait when textured).
template <bool kPacked>
PV_STAGE PathWalker::Next PathWalker::surface() {
    const TraceableScene& ts = *m_ts;
    const Scene& scene = ts.scene();
    const Hit& hit = m_hit;
    if constexpr (kPacked)
        m_sf = surface_point(scene, hit, *m_record);
    else
        m_sf = surface_point(scene, hit);
    m_mat = kPacked ? &ts.materials()[m_record->material()] : &ts.material(hit.prim);
    const Material& mat = *m_mat;
    // A normal map tilts the shading normal (materials without one skip this).
    if (mat.normal_texture != kNoIndex) [[unlikely]]
        apply_normal_map(scene, mat, hit, kPacked ? m_record->uv_at(hit.u, hit.v) : scene.uv_at(hit.prim, hit.u, hit.v),
                         -m_ray.d, m_sf);
    m_front = glm::dot(-m_ray.d, m_sf.ng) > 0.f;
    if (TraceableScene::emits(mat, m_front)) emission_found();
    if (m_depth >= m_settings->max_depth) return Next::End;
    // Only textured materials pay for the texture lookup and a local copy of the BSDF. The lookup waits until the
    // BSDF's value is needed (after the shadow ray is traced), its texels prefetched now: on large scenes their load
    // is a cache miss, which then overlaps other paths' work and Embree's traversal.
    m_tex = hit_textures(scene, mat, hit,
                         [&] { return kPacked ? m_record->uv_at(hit.u, hit.v) : scene.uv_at(hit.prim, hit.u, hit.v); });
    m_stage = Stage::Scatter;
    if (m_tex.base_color) {
        m_texels = m_tex.base_color->prefetch(m_tex.uv);
        return Next::Wait;
    }
    return Next::Go;
}

// Emission found by the BSDF-sampled ray; with NEE it is weighted so it is never counted twice.
PV_STAGE void PathWalker::emission_found() {
    const TraceableScene& ts = *m_ts;
    const Hit& hit = m_hit;
    const vec3 le = emitted_at(ts.scene(), *m_mat, hit.prim, hit.u, hit.v);
    const uint8_t group = m_groups ? m_groups->material[size_t(m_mat - ts.materials().data())] : 0;
    if (!m_nee || m_specular_bounce)
        add(m_beta * le, group);
    else
        add(m_beta * le *
                bsdf_hit_weight(m_mis, m_prev_pdf, ts.light_pdf_hit(hit.prim, m_prev_p, m_prev_n, m_sf.p, m_sf.ng)),
            group);
}

// The vertex being scattered: its shading frame, its BSDF (built with the hit's textures when first needed) and its
// ray origins off the surface.
struct PathWalker::Vertex {
    const Material& mat;
    const SurfacePoint& sf;
    const HitTextures& tex;
    const TexelFootprint& texels;
    const bool per_hit;  // the BSDF changes per hit (a texture or vertex colours)
    const Bsdf* bsdf;
    std::optional<Bsdf> textured;
    vec3 ng, ns;
    Frame frame;
    vec3 wo_world, wo;
    // Ray origins off the surface on each side of it, computed once when first needed (the shadow ray and the
    // continuation usually leave on the same side).
    vec3 origin[2];
    bool have_origin[2] = {false, false};

    [[gnu::always_inline]] Vertex(const Material& m, const SurfacePoint& s, const HitTextures& t,
                                  const TexelFootprint& tx, vec3 wo_w, bool front)
        : mat(m), sf(s), tex(t), texels(tx), per_hit(t.per_hit()), bsdf(&m.bsdf), wo_world(wo_w) {
        // Shading frame (core/render/surface.h).
        const auto [g, n] = shading_normals(sf, wo_world, front, mat.bsdf);
        ng = g;
        ns = n;
        frame = Frame(ns);
        wo = frame.to_local(wo_world);
    }
    Vertex(const Vertex&) = delete;
    // The BSDF with the hit's textures, as core/render/shading.h's hit_bsdf builds it for the AOV pass.
    [[gnu::always_inline]] const Bsdf& shade() {
        if (per_hit && !textured) {
            textured.emplace(mat.bsdf);
            apply_hit_textures(*textured, tex, tex.base_color ? tex.base_color->lookup(texels) : vec4(0.f));
            bsdf = &*textured;
        }
        return *bsdf;
    }
    [[gnu::always_inline]] vec3 origin_toward(vec3 w) {
        const int side = glm::dot(w, sf.ng) > 0.f ? 0 : 1;
        if (!have_origin[side]) {
            origin[side] = offset_ray_origin(sf.p, side == 0 ? sf.ng : -sf.ng, sf.p_error);
            have_origin[side] = true;
        }
        return origin[side];
    }
};

// This bounce's dimensions: light selection (+0), light point (+1), lobe (+2), direction (+3), roulette (+4). The
// draws are taken together so that their independent hash chains overlap; only those the vertex uses (one-lobe BSDFs
// need no lobe draw, delta ones no light or direction draws), in dimension order.
struct PathWalker::Draws {
    uint32_t dim;
    bool nee;
    float u_light_select;
    vec2 u_light;
    float u_lobe;
    vec2 u_bsdf;
};

PV_STAGE PathWalker::Draws PathWalker::draw(const Bsdf& bsdf) {
    Sampler& sampler = *m_sampler;
    const bool early = m_early;
    Draws d;
    d.dim = early ? m_early_dim : sampler.reserve(kBounceDims);
    d.nee = m_nee && !is_delta(bsdf);
    d.u_light_select = d.nee && m_select_draw ? sampler.get1d_at(d.dim) : 0.f;
    d.u_light = d.nee ? (early ? m_early_u : sampler.get2d_at(d.dim + 1)) : vec2(0.f);
    const bool one_lobe =
        std::holds_alternative<Lambertian>(bsdf) || std::holds_alternative<Mirror>(bsdf) || lambert_only(bsdf);
    d.u_lobe = one_lobe ? 0.5f : sampler.get1d_at(d.dim + 2);
    d.u_bsdf = is_delta(bsdf) ? vec2(0.5f) : sampler.get2d_at(d.dim + 3);  // delta lobes ignore it
    return d;
}

// Light sample and shadow ray, the punctual lights, the BSDF sample, roulette and the next ray.
PV_STAGE PathWalker::Next PathWalker::scatter() {
    Vertex v(*m_mat, m_sf, m_tex, m_texels, -m_ray.d, m_front);
    const Draws d = draw(*v.bsdf);
    if (m_observer && !is_delta(*v.bsdf)) [[unlikely]]
        m_observer->vertex(PathVertex{v.sf, v.ng, v.frame, v.wo, v.shade(), m_beta});
    if (d.nee) next_event(v, d);
    if (!m_ts->scene().punctual_lights.empty() && m_settings->light_sampling && !is_delta(*v.bsdf)) punctual_lights(v);
    return continue_path(v, d);
}

// Next-event estimation: the environment or a triangle (the selection probability is in the pdf), weighted by MIS.
PV_STAGE void PathWalker::next_event(Vertex& v, const Draws& d) {
    const TraceableScene& ts = *m_ts;
    LightSample ls = m_early_ls;
    if (!(m_early ? m_early_found : ts.sample_light(v.sf.p, v.ns, d.u_light_select, d.u_light, ls, true)) ||
        is_black(ls.le))
        return;
    const vec3 wi = v.frame.to_local(ls.wi);
    const float cos_gl = glm::dot(ls.wi, v.ng);
    const bool same_side = (cos_gl > 0.f) == (wi.z > 0.f);
    // An untextured BSDF is evaluated first (no shadow ray toward a black value), a textured one once the shadow ray
    // is traced: its traversal hides the load of the prefetched texels. Textures apply to reflection-only lobes, black
    // below the surface whatever the colour: no shadow ray there either (unless a metallic-roughness material
    // transmits).
    vec3 f = same_side && !v.per_hit ? eval(*v.bsdf, v.wo, wi) : vec3(0.f);
    bool visible = false;
    if (same_side && (v.per_hit ? reflects(v.wo, wi) || transmits(*v.bsdf) : !is_black(f))) {
        const Ray shadow = shadow_ray(v.origin_toward(ls.wi), ls);
        ++m_counters.shadow_rays;
        visible = !ts.occluded(shadow);
        if (visible && v.per_hit) f = eval(v.shade(), v.wo, wi);
    }
    if (!visible || is_black(f)) return;
    if (m_medium) [[unlikely]]
        f *= medium_transmittance(ls.dist);
    // The power heuristic's weight over the light pdf, w / p_l = p_l / (p_l^2 + p_b^2): one division
    // (power_heuristic's guards: an infinite p_l weighs 1 / p_l = 0).
    const float pl = ls.pdf;
    float w_over_pdf = 1.f / pl;
    if (m_mis && !std::isinf(pl)) {
        const float pb = pdf(*v.bsdf, v.wo, wi);
        const float denom = pl * pl + pb * pb;
        w_over_pdf = denom > 0.f && std::isfinite(denom) ? pl / denom : power_heuristic(pl, pb) / pl;
    }
    const vec3 added = m_beta * f * (std::fabs(wi.z) * w_over_pdf) * ls.le;
    add(added, ls.group, ls.wi);
    if (m_observer) [[unlikely]]
        m_observer->light(ls, d.u_light_select, d.u_light, added);
}

// Punctual lights (glTF KHR_lights_punctual): delta lights, reached by next-event estimation alone (no BSDF sample can
// hit them), every one at every non-delta vertex, without a random draw or MIS.
PV_STAGE void PathWalker::punctual_lights(Vertex& v) {
    const std::vector<PunctualLight>& lights = m_ts->scene().punctual_lights;
    for (size_t i = 0; i < lights.size(); ++i) {
        LightSample ls;
        if (!sample_punctual(lights[i], v.sf.p, ls)) continue;
        const vec3 wi = v.frame.to_local(ls.wi);
        if ((glm::dot(ls.wi, v.ng) > 0.f) != (wi.z > 0.f)) continue;
        const vec3 f = eval(v.shade(), v.wo, wi);
        if (is_black(f)) continue;
        ++m_counters.shadow_rays;
        if (m_ts->occluded(shadow_ray(v.origin_toward(ls.wi), ls))) continue;
        const vec3 tr = m_medium ? medium_transmittance(ls.dist) : vec3(1.f);
        add(m_beta * f * std::fabs(wi.z) * ls.le * tr, m_groups ? m_groups->punctual[i] : 0);
    }
}

// BSDF sampling for the next direction, the throughput, roulette and the next ray.
PV_STAGE PathWalker::Next PathWalker::continue_path(Vertex& v, const Draws& d) {
    auto bs = sample(v.shade(), v.wo, d.u_lobe, d.u_bsdf);
    if (!bs) return Next::End;
    vec3 wi_world = v.frame.to_world(bs->wi);
    float cos_g = glm::dot(wi_world, v.ng);
    if (((cos_g > 0.f) != (bs->wi.z > 0.f) || cos_g == 0.f) && is_delta(*v.bsdf) && v.ns != v.ng) {
        // A mirror or glass direction about the shading normal that crosses the facet on the wrong side (at a
        // smooth-shaded silhouette): the surface itself is the facet here, so take this sample about the geometric
        // normal. Each sample's weight stays the lobe's own (1 reflected, 1/eta^2 refracted), so no energy is lost or
        // gained, where ending the path darkened the rim (tests/scene/test_glass_furnace.cpp).
        const Frame geometric(v.ng);
        bs = detail::sample_other(*v.bsdf, geometric.to_local(v.wo_world), d.u_lobe, d.u_bsdf);  // out of line: rare
        if (!bs) return Next::End;
        wi_world = geometric.to_world(bs->wi);
        cos_g = glm::dot(wi_world, v.ng);
    }
    if ((cos_g > 0.f) != (bs->wi.z > 0.f) || cos_g == 0.f) return Next::End;  // would leak through
    m_beta *= bs->f * (std::fabs(bs->wi.z) / bs->pdf);
    if ((bs->wi.z > 0.f) != (v.wo.z > 0.f)) [[unlikely]] {
        // A transmission: into or out of a solid (oriented frame: wo.z > 0 is outside).
        if (m_media) [[unlikely]] {
            cross_boundary(v.mat, v.wo.z > 0.f);
        } else {
            const auto* mr = std::get_if<MetallicRoughness>(v.bsdf);  // an absorbing solid (KHR_materials_volume)
            if (mr && mr->solid()) {
                m_absorbing = v.wo.z > 0.f && !is_black(mr->sigma);
                m_sigma = mr->sigma;
            }
        }
    }
    if (!is_finite(m_beta) || is_black(m_beta)) return Next::End;
    m_specular_bounce = bs->is_delta;
    m_prev_pdf = bs->pdf;
    m_prev_p = v.sf.p;
    m_prev_n = v.ns;              // the normal sample_light was given here
    m_eta_scale *= sqr(bs->eta);  // 1 except across a refraction
    if (!roulette(d.dim)) return Next::End;
    m_ray.o = v.origin_toward(wi_world);
    m_ray.d = wi_world;
    m_ray.tmax = std::numeric_limits<float>::infinity();
    ++m_depth;
    m_stage = Stage::Trace;
    return Next::Go;
}

// Russian roulette (measured in docs/convergence.md): a path whose throughput m = max(beta) x eta_scale
// (pbrt-v4's: the radiance scaling of refraction removed) is at least kRouletteThroughput always continues; below it,
// it continues with probability m / kRouletteThroughput and survivors are divided by that, so the estimator stays
// unbiased and a surviving path's throughput is brought back to the threshold. pbrt-v4's rule (threshold 1 from the
// second vertex) plays roulette at nearly every bounce, since any surface that is not white leaves the throughput
// below 1; 0.5 measured best in efficiency 1/(relMSE x s) over the Cornell box, the mirror-and-glass box, the sunlit
// room, Sponza and Sibenik. False: the path ends.
PV_STAGE bool PathWalker::roulette(uint32_t dim) {
    if (!m_settings->russian_roulette || m_depth < 1) return true;
    const float m = max_component(m_beta) * m_eta_scale;
    if (m >= kRouletteThroughput) return true;
    const float p = m / kRouletteThroughput;
    if (m_sampler->get1d_at(dim + 4) >= p) return false;
    m_beta /= p;
    return true;
}

// The path's medium along the segment it has just traced (to its hit, or unbounded): a free-flight distance drawn
// against it. True when the segment ends in the medium (next: the scattering event's outcome) or the path ends there;
// false when the segment is passed (the throughput takes its transmittance weight) and the hit, or the escape, is
// handled as without a medium.
PV_STAGE bool PathWalker::medium_segment(bool hit, float t_hit, Next& next) {
    const HomogeneousMedium& medium = *m_medium;
    const uint32_t dim = m_sampler->reserve(kMediumDims);
    const float u_channel = m_sampler->get1d_at(dim);
    const float u_dist = m_sampler->get1d_at(dim + 1);
    const float tmax = hit ? t_hit : std::numeric_limits<float>::infinity();
    if (m_equiangular) equiangular(medium, tmax, m_sampler->get1d_at(dim + 2));
    const DistanceSample ds = sample_distance(medium, m_beta, tmax, u_channel, u_dist);
    m_beta *= ds.weight;
    if (!is_finite(m_beta) || is_black(m_beta)) {
        next = Next::End;
        return true;
    }
    if (!ds.scattered) return false;
    next = medium_scatter(ds.t, tmax, ds.pdf);
    if (next == Next::End) return true;
    next = Next::Wait;  // the next segment is traced at the next step (m_stage is Trace)
    return true;
}

// The path's medium's transmittance over a shadow ray of length dist (infinite toward the environment). A shadow ray
// stops at any surface (TraceableScene::occluded), so it never crosses a medium boundary: the medium it starts in is
// the only one along it.
inline vec3 PathWalker::medium_transmittance(float dist) const {
    const vec3 st = m_medium->sigma_t();
    vec3 tr(0.f);
    for (int c = 0; c < 3; ++c) tr[c] = st[c] > 0.f ? (std::isinf(dist) ? 0.f : std::exp(-st[c] * dist)) : 1.f;
    return tr;
}

// The medium stack (docs/media.md): a transmission into a closed solid (a dielectric, or a metallic-roughness
// material that is not thin-walled: what oriented_eta tells apart) pushes its material, one out of a solid pops the
// innermost. The path's medium is the innermost solid's interior medium, none when it has none (its
// KHR_materials_volume attenuation, if any, then applies by Beer-Lambert), or the fog outside every solid. Deeper
// than kMaxMediumNesting, the innermost entry is replaced; leaving with an empty stack (a path that started inside a
// solid) leaves it in the fog.
PV_STAGE void PathWalker::cross_boundary(const Material& mat, bool entering) {
    if (!(oriented_eta(mat.bsdf) > 0.f)) return;  // a thin sheet: the path stays where it was
    if (entering) {
        if (m_nesting == kMaxMediumNesting) --m_nesting;
        m_solids[m_nesting++] = &mat;
    } else if (m_nesting > 0) {
        --m_nesting;
    }
    m_absorbing = false;
    if (m_nesting == 0) {
        m_medium = m_ts->fog().empty() ? nullptr : &m_ts->fog();
        return;
    }
    const Material& inner = *m_solids[m_nesting - 1];
    m_medium = inner.medium.empty() ? nullptr : &inner.medium;
    const auto* mr = std::get_if<MetallicRoughness>(&inner.bsdf);
    if (!m_medium && mr && mr->solid() && !is_black(mr->sigma)) {
        m_absorbing = true;
        m_sigma = mr->sigma;
    }
}

// Equiangular sampling toward each point and spot light (Kulla and Fajardo 2012; core/scene/medium.h) along the
// segment just traced, for the light scattered once toward the path at a point of it: a second strategy beside
// distance sampling's scattering events, whose estimate of the same light medium_scatter weighs by the power
// heuristic against this one's pdf, as this one's is weighed against distance sampling's density (the channel-averaged
// pdf of a scattering event at t). Skipped where a scattering event would end the path before its light samples.
PV_STAGE void PathWalker::equiangular(const HomogeneousMedium& medium, float tmax, float u) {
    if (m_depth >= m_settings->max_depth) return;
    const vec3 probs = channel_probabilities(medium, m_beta);
    const std::vector<PunctualLight>& lights = m_ts->scene().punctual_lights;
    for (size_t i = 0; i < lights.size(); ++i) {
        const PunctualLight& light = lights[i];
        if (light.type == PunctualLight::Type::Directional) continue;
        const EquiangularSegment e = equiangular_segment(m_ray.o, m_ray.d, light.position, tmax);
        if (!e.valid()) continue;
        const float t = sample_equiangular(e, tmax, u);
        const float pe = equiangular_pdf(e, t);
        const vec3 p = m_ray.o + t * m_ray.d;
        LightSample ls;
        if (!(pe > 0.f) || !sample_punctual(light, p, ls)) continue;
        ++m_counters.shadow_rays;
        if (m_ts->occluded(shadow_ray(p, ls))) continue;
        const float w = power_heuristic(pe, distance_pdf(medium, probs, t, true));
        add(m_beta * medium.sigma_s * medium.transmittance(t) *
                (hg_phase(glm::dot(m_ray.d, ls.wi), medium.g) * w / pe) * ls.le * medium_transmittance(ls.dist),
            m_groups ? m_groups->punctual[i] : 0);
    }
}

// A scattering event at distance t along the segment in the path's medium: next-event estimation (a light sample,
// its shadow ray and the medium's transmittance along it, weighted against phase sampling by the power heuristic),
// the punctual lights (point and spot lights weighted against equiangular sampling), then the phase function's sample
// (weight 1: it is sampled exactly), roulette and the next ray from the point.
PV_STAGE PathWalker::Next PathWalker::medium_scatter(float t, float tmax, float pdf_t) {
    const TraceableScene& ts = *m_ts;
    const float g = m_medium->g;
    const vec3 p = m_ray.o + t * m_ray.d;
    ++m_counters.vertices;
    if (m_depth >= m_settings->max_depth) return Next::End;
    Sampler& sampler = *m_sampler;
    const uint32_t dim = sampler.reserve(kBounceDims);
    const vec3 d = m_ray.d;
    // Next-event estimation from the medium point (no normal: the light sampler is given a zero one).
    if (m_nee) {
        const float u_select = m_select_draw ? sampler.get1d_at(dim) : 0.f;
        const vec2 u_light = sampler.get2d_at(dim + 1);
        LightSample ls;
        if (ts.sample_light(p, vec3(0.f), u_select, u_light, ls, true) && !is_black(ls.le)) {
            const float ph = hg_phase(glm::dot(d, ls.wi), g);
            ++m_counters.shadow_rays;
            if (ph > 0.f && !ts.occluded(shadow_ray(p, ls))) {
                const float pl = ls.pdf;
                const float w = m_mis ? power_heuristic(pl, ph) : 1.f;
                add(m_beta * (ph * w / pl) * ls.le * medium_transmittance(ls.dist), ls.group, ls.wi);
            }
        }
    }
    if (m_settings->light_sampling)
        for (size_t i = 0; i < ts.scene().punctual_lights.size(); ++i) {
            const PunctualLight& light = ts.scene().punctual_lights[i];
            LightSample ls;
            if (!sample_punctual(light, p, ls)) continue;
            ++m_counters.shadow_rays;
            if (ts.occluded(shadow_ray(p, ls))) continue;
            float w = 1.f;
            if (m_equiangular && light.type != PunctualLight::Type::Directional) {
                const EquiangularSegment e = equiangular_segment(m_ray.o, d, light.position, tmax);
                if (e.valid()) w = power_heuristic(pdf_t, equiangular_pdf(e, t));
            }
            add(m_beta * (hg_phase(glm::dot(d, ls.wi), g) * w) * ls.le * medium_transmittance(ls.dist),
                m_groups ? m_groups->punctual[i] : 0);
        }
    // Phase sampling: the next direction.
    const vec3 wi = sample_hg(d, g, sampler.get2d_at(dim + 3));
    m_specular_bounce = false;
    m_prev_pdf = hg_phase(glm::dot(d, wi), g);
    m_prev_p = p;
    m_prev_n = vec3(0.f);
    if (!roulette(dim)) return Next::End;
    m_ray.o = p;
    m_ray.d = wi;
    m_ray.tmax = std::numeric_limits<float>::infinity();
    ++m_depth;
    m_stage = Stage::Trace;
    return Next::Go;
}

#undef PV_STAGE

// A contribution credited to its light group; the environment's is split between the sky and the sun by their
// shares of its radiance toward dir (one light for MIS, so the same weight applies to both parts).
void PathWalker::credit(vec3 c, uint8_t group, vec3 dir) {
    if (group != kEnvironmentGroup) {
        m_group_L[group] += c;
        return;
    }
    const LightGroups& g = *m_groups;
    if (g.sky == g.sun) {
        m_group_L[g.sky] += c;
        return;
    }
    const Environment& env = m_ts->environment();
    const vec3 sun = env.eval_sun(dir);
    if (is_black(sun)) {
        m_group_L[g.sky] += c;
        return;
    }
    const vec3 le = sun + env.eval_sky(dir);
    vec3 to_sun(0.f);
    for (int k = 0; k < 3; ++k) to_sun[k] = le[k] > 0.f ? c[k] * (sun[k] / le[k]) : 0.f;
    m_group_L[g.sun] += to_sun;
    m_group_L[g.sky] += c - to_sun;
}

vec3 trace_path(const TraceableScene& ts, const RenderSettings& settings, Ray ray, Sampler& sampler,
                PathCounters& counters) {
    PathWalker w;
    w.start(ts, settings, ray, sampler);
    while (w.step()) {
    }
    counters += w.counters();
    return w.radiance();
}

}  // namespace pv
