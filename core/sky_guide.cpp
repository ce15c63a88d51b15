// core/sky_guide.cpp: the learned sky distribution and its training pre-pass (see sky_guide.h).
#include "core/sky_guide.h"

#include <algorithm>
#include <cmath>

#include "core/camera.h"
#include "core/environment.h"
#include "core/integrator.h"
#include "core/parallel.h"
#include "core/rng.h"
#include "core/surface.h"
#include "core/traceable_scene.h"
#include "core/warp.h"

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
    return settings.sky_guide && settings.light_sampling && ts.environment_selection_probability() > 0.f &&
           ts.environment().sun_probability() < 1.f && ts.portal_probability() == 0.f;
}

namespace {

constexpr int kTrainDepth = 5;    // vertices per training path at most
constexpr int kShadowRays = 2;    // sky shadow rays per non-delta vertex
constexpr int kPathsPerCell = 2;  // per training grid cell
constexpr int kChunkRows = 16;    // grid rows per chunk (one histogram each)

// One training path from camera ray `ray`: at each non-delta vertex, kShadowRays shadow rays toward directions from
// the sky's own sampling add luminance(beta f |cos| Le_sky) / pdf_sky of the unoccluded ones to `h` (the vertex's
// cell of `grid`, the direction's bin). The path continues by BSDF sampling, with the integrator's shading normals
// and roulette.
void train_path(const TraceableScene& ts, const SkyGuideGrid& grid, Ray ray, Pcg32& rng, std::vector<double>& h) {
    const Scene& scene = ts.scene();
    const Environment& env = ts.environment();
    const float p_sun = env.sun_probability();
    auto u1 = [&] { return rng.next_float(); };
    auto u2 = [&] {
        const float a = rng.next_float();
        return vec2(a, rng.next_float());
    };
    vec3 beta(1.f);
    for (int depth = 0; depth < kTrainDepth; ++depth) {
        Hit hit;
        if (!ts.intersect(ray, hit)) return;
        const SurfacePoint sf = surface_point(scene, hit);
        const Material& mat = ts.material(hit.prim);
        Bsdf bsdf = mat.bsdf;
        if (mat.base_color_texture != kNoIndex)
            set_base_color(bsdf,
                           vec3(scene.textures[mat.base_color_texture].lookup(scene.uv_at(hit.prim, hit.u, hit.v))));
        const vec3 wo_world = -ray.d;
        const auto [ng, ns] = shading_normals(sf, wo_world, glm::dot(wo_world, sf.ng) > 0.f, mat.bsdf);
        const Frame frame(ns);
        const vec3 wo = frame.to_local(wo_world);
        auto origin_toward = [&sf](vec3 w) {
            return offset_ray_origin(sf.p, glm::dot(w, sf.ng) > 0.f ? sf.ng : -sf.ng, sf.p_error);
        };
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

// One training iteration: the histogram of luminance(beta f |cos| Le_sky V) / pdf over the bins, summed over every
// path, per cell of `grid` (the vertex's). kPathsPerCell paths per cell of a gw x gh grid over the film.
std::vector<double> train_iteration(const TraceableScene& ts, const Camera& camera, int gw, int gh, uint64_t seed,
                                    const SkyGuideGrid& grid) {
    const size_t bins = size_t(grid.cells()) * size_t(SkyGuide::kBins);
    const int chunks = (gh + kChunkRows - 1) / kChunkRows;
    std::vector<std::vector<double>> hist(size_t(chunks), std::vector<double>(bins, 0.0));
    const vec2 cell_size(float(camera.width()) / float(gw), float(camera.height()) / float(gh));
    parallel_for_range(0, chunks, [&](const tbb::blocked_range<int>& range) {
        enable_ftz_daz();
        for (int chunk = range.begin(); chunk != range.end(); ++chunk)
            for (int gy = chunk * kChunkRows; gy < std::min(gh, (chunk + 1) * kChunkRows); ++gy)
                for (int gx = 0; gx < gw; ++gx)
                    for (int s = 0; s < kPathsPerCell; ++s) {
                        const uint64_t key = hash_combine(hash_combine(seed, uint64_t(gx)), uint64_t(gy));
                        Pcg32 rng;
                        rng.seed(hash_combine(key, uint64_t(s)), key);
                        const float fx = rng.next_float(), fy = rng.next_float();
                        const float lx = rng.next_float(), ly = rng.next_float();
                        const vec2 film = (vec2(float(gx), float(gy)) + vec2(fx, fy)) * cell_size;
                        train_path(ts, grid, camera.generate(film, vec2(lx, ly)), rng, hist[size_t(chunk)]);
                    }
    });
    std::vector<double> total(bins, 0.0);
    for (const std::vector<double>& h : hist)
        for (size_t i = 0; i < total.size(); ++i) total[i] += h[i];
    return total;
}

}  // namespace

std::shared_ptr<const SkyGuide> train_sky_guide(const TraceableScene& ts, const RenderSettings& settings,
                                                const Camera& camera) {
    if (!sky_guide_applies(ts, settings)) return nullptr;
    // A coarse grid in the render's aspect, whatever the render's size.
    const double aspect = double(camera.width()) / double(camera.height());
    const int gw = std::max(1, int(std::lround(std::sqrt(double(kSkyGuideTrainingCells) * aspect))));
    const int gh = std::max(1, int(std::lround(double(kSkyGuideTrainingCells) / double(gw))));
    const uint64_t seed = hash_combine(hash_combine(0x736b79677569ull, settings.seed), 1);
    // The grid: about kSkyGuideCells cubic-ish cells over the scene's bounds.
    vec3 lo, hi;
    ts.scene().bounds(lo, hi);
    const vec3 extent = glm::max(hi - lo, vec3(1e-6f) * max_component(hi - lo));
    const float side = std::cbrt(extent.x * extent.y * extent.z / float(kSkyGuideCells));
    glm::ivec3 res(1);
    for (int a = 0; a < 3; ++a) res[a] = std::clamp(int(std::lround(extent[a] / side)), 1, 16);
    const SkyGuideGrid grid(res, lo, lo + extent);
    std::vector<double> weights = train_iteration(ts, camera, gw, gh, seed, grid);
    auto guide = std::make_shared<SkyGuide>(weights, grid);
    if (!guide->valid()) return nullptr;
    return guide;
}

}  // namespace pv
