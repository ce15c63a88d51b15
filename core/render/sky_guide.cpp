// core/render/sky_guide.cpp: the learned sky distribution and its training pre-pass (see sky_guide.h).
#include "core/render/sky_guide.h"

#include <algorithm>
#include <cmath>

#include "core/base/parallel.h"
#include "core/render/integrator.h"
#include "core/render/shading.h"
#include "core/render/surface.h"
#include "core/render/traceable_scene.h"
#include "core/sampling/rng.h"
#include "core/sampling/warp.h"
#include "core/scene/camera.h"
#include "core/scene/environment.h"

namespace pv {

SkyGuideGrid::SkyGuideGrid(glm::ivec3 r, vec3 l, vec3 hi) : res(r), lo(l) {
    scale = vec3(res) / glm::max(hi - lo, vec3(1e-30f));
    max = vec3(res) - vec3(0.5f);  // int() of it is res - 1
}

SkyGuide::SkyGuide(const std::vector<double>& weights, const SkyGuideGrid& grid) {
    if (!grid.valid()) return;
    const size_t cells = size_t(grid.cells()), n = size_t(kBins);
    if (weights.size() != cells * n) return;
    auto clean = [](double w) { return std::isfinite(w) && w > 0.0 ? w : 0.0; };
    std::vector<double> global(n, 0.0);
    for (size_t c = 0; c < cells; ++c)
        for (size_t i = 0; i < n; ++i) global[i] += clean(weights[c * n + i]);
    double global_total = 0.0;
    for (double w : global) global_total += w;
    if (!(global_total > 0.0) || !std::isfinite(global_total)) return;
    std::vector<CellTable> tables(cells);
    std::vector<float> pmf(cells * n);
    std::vector<double> w(n);
    for (size_t c = 0; c < cells; ++c) {
        double total = 0.0;
        for (size_t i = 0; i < n; ++i) total += clean(weights[c * n + i]);
        for (size_t i = 0; i < n; ++i)
            w[i] =
                total > 0.0 ? clean(weights[c * n + i]) + kGlobalShare * total * global[i] / global_total : global[i];
        const DiscreteDistribution d(w);
        // Cannot fail with a positive global total (and 128 items always make 128 slots); stay consistent regardless.
        if (d.empty() || d.slot_count() != n || d.slot_shift() != kSlotShift) return;
        for (size_t i = 0; i < n; ++i) {
            uint32_t threshold, own, alias;
            d.slot(i, &threshold, &own, &alias);
            tables[c].slot[i] = threshold << 14 | own << 7 | alias;
            pmf[c * n + i] = d.pmf(i);
            tables[c].pdf[i] = d.pmf(i) * (float(kBins) / (4.f * kPi));
        }
    }
    m_grid = grid;
    m_cells = std::move(tables);
    m_pmf = std::move(pmf);
}

int SkyGuide::bin(vec3 d) {
    // Fractional band and column, clamped inside the grid before the conversion to int (NaN: 0).
    const float b = (1.f - d.y) * (0.5f * float(kBands));
    const int band = b > 0.f ? int(std::min(b, float(kBands) - 0.5f)) : 0;
    float phi = environment_atan2_approx(-d.z, d.x) * kInv2Pi;  // turns, in [-1/2, 1/2]
    if (phi < 0.f) phi += 1.f;
    const float c = phi * float(kColumns);
    const int col = c > 0.f ? int(std::min(c, float(kColumns) - 0.5f)) : 0;
    return band * kColumns + col;
}

vec3 SkyGuide::sample_in(int cell, float u_bin, vec2 u) const {
    // DiscreteDistribution::sample on the packed table.
    const uint32_t k = std::min(uint32_t(u_bin * 0x1p23f), (1u << DiscreteDistribution::kBits) - 1u);
    const uint32_t slot = m_cells[size_t(cell)].slot[k >> kSlotShift];
    const uint32_t i = (k & ((1u << kSlotShift) - 1u)) < (slot >> 14) ? (slot >> 7) & 127u : slot & 127u;
    const uint32_t band = i / kColumns, col = i % kColumns;
    // Uniform by area: y = cos(theta) uniform in the band, phi uniform in the column.
    const float y = 1.f - 2.f * (float(band) + u.x) / float(kBands);
    const float r = std::sqrt(std::max(0.f, 1.f - y * y));
    const vec2 cs = cos_sin_turns((float(col) + u.y) / float(kColumns));
    return vec3(r * cs.x, y, -r * cs.y);
}

bool sky_guide_applies(const TraceableScene& ts, const RenderSettings& settings) {
    return settings.sky_guide != SkyGuideMode::Off && settings.light_sampling &&
           ts.environment_selection_probability() > 0.f && ts.environment().sun_probability() < 1.f &&
           ts.portal_probability() == 0.f;
}

namespace {

constexpr int kTrainDepth = 5;    // vertices per training path at most
constexpr int kShadowRays = 2;    // sky shadow rays per non-delta vertex
constexpr int kPathsPerCell = 2;  // per training grid cell: two, so that their difference measures the noise
constexpr int kChunkRows = 16;    // grid rows per chunk (one histogram each)

// A sky sample of the render's own next-event estimation, found unoccluded by a training path: what the guide would
// change. c2 = its contribution squared, pdf_sky = the sky's own density toward dir.
struct SkyRecord {
    vec3 p, dir;
    float c2, pdf_sky;
};

// What one training path measured for the decision (SkyGuideTraining): y = its NEE-only estimate of the pixel
// (the render's light sampling, one sample per non-delta vertex, without MIS; emission seen directly or after a
// delta bounce), and the parts of it from the sky and from the sun.
struct PathTally {
    double y = 0.0, sky = 0.0, sun = 0.0;
};

// One training path from camera ray `ray`: at each non-delta vertex, kShadowRays shadow rays toward directions from
// the sky's own sampling add luminance(beta f |cos| Le_sky) / pdf_sky of the unoccluded ones to `h` (the vertex's
// cell of `grid`, the direction's bin). The path continues by BSDF sampling, with the integrator's shading normals
// and roulette. With its own generator `nee` (so the guide does not depend on it; none: skipped), one light sample
// as the render draws it (sample_light; no guide may be set) adds to `tally`, and its unoccluded sky samples to
// `records`.
void train_path(const TraceableScene& ts, const SkyGuideGrid& grid, Ray ray, Pcg32& rng, Pcg32* nee,
                std::vector<double>& h, PathTally& tally, std::vector<SkyRecord>& records) {
    const Scene& scene = ts.scene();
    const Environment& env = ts.environment();
    const float p_sun = env.sun_probability(), p_env = ts.environment_selection_probability();
    auto u1 = [&] { return rng.next_float(); };
    auto u2 = [&] {
        const float a = rng.next_float();
        return vec2(a, rng.next_float());
    };
    vec3 beta(1.f);
    bool emission_counts = true;  // camera ray or after a delta bounce: next-event estimation did not see it
    for (int depth = 0; depth < kTrainDepth; ++depth) {
        Hit hit;
        if (!ts.intersect(ray, hit)) {
            if (emission_counts) tally.y += double(luminance(beta * ts.emitted_escape(ray.d)));
            return;
        }
        // The surface as the integrator shades it (core/render/shading.h): the normal map, textures and vertex colours.
        SurfacePoint sf = surface_point(scene, hit);
        const Material& mat = ts.material(hit.prim);
        const vec3 wo_world = -ray.d;
        apply_normal_map(scene, mat, hit, scene.uv_at(hit.prim, hit.u, hit.v), wo_world, sf);
        const Bsdf bsdf = hit_bsdf(mat, hit_textures(scene, mat, hit));
        const bool front = glm::dot(wo_world, sf.ng) > 0.f;
        if (emission_counts && TraceableScene::emits(mat, front))
            tally.y += double(luminance(beta * emitted_at(scene, mat, hit.prim, hit.u, hit.v)));
        const auto [ng, ns] = shading_normals(sf, wo_world, front, mat.bsdf);
        const Frame frame(ns);
        const vec3 wo = frame.to_local(wo_world);
        auto origin_toward = [&sf](vec3 w) {
            return offset_ray_origin(sf.p, glm::dot(w, sf.ng) > 0.f ? sf.ng : -sf.ng, sf.p_error);
        };
        emission_counts = is_delta(bsdf);
        if (!is_delta(bsdf)) {
            const size_t cell = size_t(grid.cell(sf.p));
            for (int k = 0; k < kShadowRays; ++k) {
                // The sky's part of the environment's sampling (u.x past the sun's share).
                const vec2 u = u2();
                const std::optional<EnvironmentSample> es =
                    env.sample(vec2(std::min(p_sun + u.x * (1.f - p_sun), kOneMinusEpsilon), u.y));
                if (!es) continue;
                const float pdf = env.pdf_sky(es->wi);
                const vec3 wi = frame.to_local(es->wi);
                if (!(pdf > 0.f) || (glm::dot(es->wi, ng) > 0.f) != (wi.z > 0.f)) continue;
                const float value = luminance(beta * eval(bsdf, wo, wi) * env.eval_sky(es->wi)) * std::fabs(wi.z) / pdf;
                if (!(value > 0.f) || !std::isfinite(value)) continue;
                Ray shadow;
                shadow.o = origin_toward(es->wi);
                shadow.d = es->wi;
                shadow.tmax = std::numeric_limits<float>::infinity();
                if (ts.occluded(shadow)) continue;
                h[cell * size_t(SkyGuide::kBins) + size_t(SkyGuide::bin(es->wi))] +=
                    double(value) / double(kShadowRays);
            }
            // The render's next-event estimate at this vertex (the environment picked when u_select < p_env, its
            // sky when u.x >= p_sun, as sample_light and Environment::sample choose).
            const float u_select = nee ? nee->next_float() : 0.f;
            const float ux = nee ? nee->next_float() : 0.f;
            const vec2 u(ux, nee ? nee->next_float() : 0.f);
            LightSample ls;
            if (nee && ts.sample_light(sf.p, ns, u_select, u, ls) && !is_black(ls.le)) {
                const vec3 wi = frame.to_local(ls.wi);
                const float c = (glm::dot(ls.wi, ng) > 0.f) == (wi.z > 0.f)
                                    ? luminance(beta * eval(bsdf, wo, wi) * ls.le) * std::fabs(wi.z) / ls.pdf
                                    : 0.f;
                if (c > 0.f && std::isfinite(c) && !ts.occluded(shadow_ray(origin_toward(ls.wi), ls))) {
                    tally.y += double(c);
                    if (u_select < p_env && u.x >= p_sun && env.pdf_sun(ls.wi) == 0.f) {
                        tally.sky += double(c);
                        records.push_back(SkyRecord{sf.p, ls.wi, c * c, env.pdf_sky(ls.wi)});
                    } else if (u_select < p_env) {
                        tally.sun += double(c);
                    }
                }
            }
        }
        const auto bs = sample(bsdf, wo, u1(), u2());
        if (!bs) return;
        const vec3 wi_world = frame.to_world(bs->wi);
        const float cos_g = glm::dot(wi_world, ng);
        if ((cos_g > 0.f) != (bs->wi.z > 0.f) || cos_g == 0.f) return;
        beta *= bs->f * (std::fabs(bs->wi.z) / bs->pdf);
        if (!is_finite(beta) || is_black(beta)) return;
        const float m = max_component(beta);
        if (depth >= 1 && m < kRouletteThroughput) {
            if (u1() * kRouletteThroughput >= m) return;
            beta *= kRouletteThroughput / m;
        }
        ray.o = origin_toward(wi_world);
        ray.d = wi_world;
        ray.tmax = std::numeric_limits<float>::infinity();
    }
}

// What a training pass gathered: the histogram of luminance(beta f |cos| Le_sky V) / pdf over the bins, per cell
// of the grid and per path of the training cell's pair (s = 0, 1: two guides, each judged on the other's samples);
// per grid cell, each path's tally; and the sky records of each path of the pair.
struct TrainingData {
    std::vector<double> hist[kPathsPerCell];
    std::vector<PathTally> tally;  // (gy gw + gx) kPathsPerCell + s
    std::vector<SkyRecord> records[kPathsPerCell];
};

// One training pass: kPathsPerCell paths per cell of a gw x gh grid over the film; `judged`: with the tallies and
// records for the decision.
TrainingData train_iteration(const TraceableScene& ts, const Camera& camera, int gw, int gh, uint64_t seed,
                             const SkyGuideGrid& grid, bool judged) {
    const size_t bins = size_t(grid.cells()) * size_t(SkyGuide::kBins);
    const int chunks = (gh + kChunkRows - 1) / kChunkRows;
    struct Chunk {
        std::vector<double> hist[kPathsPerCell];
        std::vector<SkyRecord> records[kPathsPerCell];
    };
    std::vector<Chunk> parts(static_cast<size_t>(chunks));
    TrainingData out;
    out.tally.resize(size_t(gw) * size_t(gh) * kPathsPerCell);
    const vec2 cell_size(float(camera.width()) / float(gw), float(camera.height()) / float(gh));
    parallel_for_range(0, chunks, [&](const tbb::blocked_range<int>& range) {
        enable_ftz_daz();
        for (int chunk = range.begin(); chunk != range.end(); ++chunk) {
            Chunk& part = parts[size_t(chunk)];
            for (std::vector<double>& h : part.hist) h.assign(bins, 0.0);
            for (int gy = chunk * kChunkRows; gy < std::min(gh, (chunk + 1) * kChunkRows); ++gy)
                for (int gx = 0; gx < gw; ++gx)
                    for (int s = 0; s < kPathsPerCell; ++s) {
                        const uint64_t key = hash_combine(hash_combine(seed, uint64_t(gx)), uint64_t(gy));
                        Pcg32 rng, nee;
                        rng.seed(hash_combine(key, uint64_t(s)), key);
                        nee.seed(hash_combine(key, uint64_t(s) + 0x6e6565ull), key + 1);
                        const float fx = rng.next_float(), fy = rng.next_float();
                        const float lx = rng.next_float(), ly = rng.next_float();
                        const vec2 film = (vec2(float(gx), float(gy)) + vec2(fx, fy)) * cell_size;
                        const size_t t = (size_t(gy) * size_t(gw) + size_t(gx)) * kPathsPerCell + size_t(s);
                        train_path(ts, grid, camera.generate(film, vec2(lx, ly)), rng, judged ? &nee : nullptr,
                                   part.hist[s], out.tally[t], part.records[s]);
                    }
        }
    });
    for (int s = 0; s < kPathsPerCell; ++s) {
        out.hist[s].assign(bins, 0.0);
        for (Chunk& part : parts) {
            for (size_t i = 0; i < bins; ++i) out.hist[s][i] += part.hist[s][i];
            out.records[s].insert(out.records[s].end(), part.records[s].begin(), part.records[s].end());
        }
    }
    return out;
}

// The decision's statistics from a training pass (see SkyGuideTraining); `guide`: the pass's own.
void judge(const TrainingData& data, const SkyGuide& guide, SkyGuideTraining& t) {
    // The variance of the pixel estimate: half the squared difference of the pair's estimates, summed over the
    // cells; and the parts of the estimates.
    double noise = 0.0, y = 0.0, sky = 0.0, sun = 0.0;
    for (size_t c = 0; c + 1 < data.tally.size(); c += kPathsPerCell) {
        const PathTally &a = data.tally[c], &b = data.tally[c + 1];
        noise += 0.5 * (a.y - b.y) * (a.y - b.y);
        for (const PathTally* p : {&a, &b}) y += p->y, sky += p->sky, sun += p->sun;
    }
    // The second moment the guide's mixture would take out of the sky samples (their directions were drawn apart
    // from the guide's training rays): c^2 (1 - pdf_sky / pdf_mixture); per path of a pair, as the noise.
    double saved = 0.0;
    const float q = TraceableScene::kSkyGuideProbability;
    for (const std::vector<SkyRecord>& records : data.records)
        for (const SkyRecord& r : records) {
            const float mix = (1.f - q) * r.pdf_sky + q * (guide.valid() ? guide.pdf(r.p, r.dir) : r.pdf_sky);
            saved += double(r.c2) * (1.0 - double(r.pdf_sky) / double(mix));
        }
    saved /= double(kPathsPerCell);
    t.variance_ratio = noise > 0.0 ? std::max(0.0, 1.0 - saved / noise) : 1.0;
    t.sky_share = y > 0.0 ? sky / y : 0.0;
    t.sun_share = sky + sun > 0.0 ? sun / (sky + sun) : 0.0;
}

}  // namespace

SkyGuideTraining train_sky_guide_judged(const TraceableScene& ts, const RenderSettings& settings,
                                        const Camera& camera) {
    SkyGuideTraining t;
    if (!sky_guide_applies(ts, settings)) return t;
    const uint64_t seed = hash_combine(hash_combine(0x736b79677569ull, settings.seed), 1);
    // The grid: about kSkyGuideCells cubic-ish cells over the scene's bounds.
    vec3 lo, hi;
    ts.scene().bounds(lo, hi);
    const vec3 extent = glm::max(hi - lo, vec3(1e-6f) * max_component(hi - lo));
    const float side = std::cbrt(extent.x * extent.y * extent.z / float(kSkyGuideCells));
    glm::ivec3 res(1);
    for (int a = 0; a < 3; ++a) res[a] = std::clamp(int(std::lround(extent[a] / side)), 1, 16);
    const SkyGuideGrid grid(res, lo, lo + extent);
    // A grid of about `cells` cells over the film in the render's aspect.
    const double aspect = double(camera.width()) / double(camera.height());
    auto film_grid = [aspect](double cells) {
        const int gw = std::max(1, int(std::lround(std::sqrt(cells * aspect))));
        return glm::ivec2(gw, std::max(1, int(std::lround(cells / double(gw)))));
    };
    // The pilot: a path per pixel (two per cell), kSkyGuidePilotCells to kSkyGuideMaxPilotCells cells; the decision
    // comes from it.
    const glm::ivec2 pilot =
        film_grid(std::clamp(double(camera.width()) * double(camera.height()) / double(kPathsPerCell),
                             double(kSkyGuidePilotCells), double(kSkyGuideMaxPilotCells)));
    const TrainingData data = train_iteration(ts, camera, pilot.x, pilot.y, seed, grid, true);
    std::vector<double> weights(data.hist[0].size());
    for (size_t i = 0; i < weights.size(); ++i) weights[i] = data.hist[0][i] + data.hist[1][i];
    judge(data, SkyGuide(weights, grid), t);
    // The rest of kSkyGuideTrainingCells, where the guide will be used (not for the decision: it needs no tallies).
    const bool pays = t.variance_ratio * kSkyGuideRelativeCost < 1.0;
    const bool wanted = settings.sky_guide == SkyGuideMode::On || pays;
    const int rest = kSkyGuideTrainingCells - pilot.x * pilot.y;
    if (wanted && rest >= kSkyGuidePilotCells / 4) {
        const glm::ivec2 more = film_grid(double(rest));
        const TrainingData d2 = train_iteration(ts, camera, more.x, more.y, hash_combine(seed, 2), grid, false);
        for (size_t i = 0; i < weights.size(); ++i) weights[i] += d2.hist[0][i] + d2.hist[1][i];
    }
    auto guide = std::make_shared<SkyGuide>(weights, grid);
    if (guide->valid()) t.guide = std::move(guide);
    t.use = t.guide && pays;
    return t;
}

std::shared_ptr<const SkyGuide> train_sky_guide(const TraceableScene& ts, const RenderSettings& settings,
                                                const Camera& camera) {
    return train_sky_guide_judged(ts, settings, camera).guide;
}

}  // namespace pv
