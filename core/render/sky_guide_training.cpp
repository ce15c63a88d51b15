// core/render/sky_guide_training.cpp: the sky guide's training pre-pass on the integrator's PathWalker, and the
// guide's lifecycle in a render (see sky_guide_training.h).
#include "core/render/sky_guide_training.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/base/parallel.h"
#include "core/sampling/rng.h"
#include "core/scene/environment.h"

namespace pv {

bool sky_guide_applies(const TraceableScene& ts, const RenderSettings& settings) {
    return settings.sky_guide != SkyGuideMode::Off && settings.light_sampling &&
           ts.environment_selection_probability() > 0.f && ts.environment().sun_probability() < 1.f &&
           ts.portal_probability() == 0.f;
}

namespace {

constexpr int kTrainDepth = 5;    // vertices per training path that take light samples, at most
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
// (the walker's radiance with the render's light sampling, one sample per non-delta vertex, without MIS: emission
// found by a BSDF sample counts only where light sampling cannot pick it), and the parts of it from the sky and from
// the sun.
struct PathTally {
    double y = 0.0, sky = 0.0, sun = 0.0;
};

// The settings of the training's PathWalker: the render's light sampler, no MIS (judged) or no light sampling, at
// most kTrainDepth scattering vertices, roulette on.
RenderSettings training_walk(const RenderSettings& settings, bool judged) {
    RenderSettings s = settings;
    s.light_sampling = judged;
    s.mis = false;
    s.russian_roulette = true;
    s.max_depth = kTrainDepth;
    s.sampler = SamplerKind::Independent;
    return s;
}

// Watches one training path (a PathWalker's, PathObserver): at each vertex that takes a light sample, kShadowRays
// shadow rays toward directions from the sky's own sampling add luminance(beta f |cos| Le_sky) / pdf_sky of the
// unoccluded ones to `h` (the vertex's cell of `grid`, the direction's bin), with draws from `rng` (so the guide does
// not depend on the walker's). Judged (the walker doing next-event estimation), each unoccluded light sample adds
// its part to `tally`'s sky or sun, and a sky sample to `records`.
class TrainingObserver final : public PathObserver {
public:
    TrainingObserver(const TraceableScene& ts, const SkyGuideGrid& grid, Pcg32& rng, std::vector<double>& h,
                     PathTally& tally, std::vector<SkyRecord>& records)
        : m_ts(ts), m_env(ts.environment()), m_grid(grid), m_rng(rng), m_h(h), m_tally(tally), m_records(records) {}

    void vertex(const PathVertex& v) override {
        const float p_sun = m_env.sun_probability();
        const SurfacePoint& sf = v.sf;
        m_p = sf.p;
        const size_t cell = size_t(m_grid.cell(sf.p));
        for (int k = 0; k < kShadowRays; ++k) {
            // The sky's part of the environment's sampling (u.x past the sun's share).
            const float ux = m_rng.next_float();
            const vec2 u(ux, m_rng.next_float());
            const std::optional<EnvironmentSample> es =
                m_env.sample(vec2(std::min(p_sun + u.x * (1.f - p_sun), kOneMinusEpsilon), u.y));
            if (!es) continue;
            const float pdf = m_env.pdf_sky(es->wi);
            const vec3 wi = v.frame.to_local(es->wi);
            if (!(pdf > 0.f) || (glm::dot(es->wi, v.ng) > 0.f) != (wi.z > 0.f)) continue;
            const float value =
                luminance(v.beta * eval(v.bsdf, v.wo, wi) * m_env.eval_sky(es->wi)) * std::fabs(wi.z) / pdf;
            if (!(value > 0.f) || !std::isfinite(value)) continue;
            Ray shadow;
            shadow.o = offset_ray_origin(sf.p, glm::dot(es->wi, sf.ng) > 0.f ? sf.ng : -sf.ng, sf.p_error);
            shadow.d = es->wi;
            shadow.tmax = std::numeric_limits<float>::infinity();
            if (m_ts.occluded(shadow)) continue;
            m_h[cell * size_t(SkyGuide::kBins) + size_t(SkyGuide::bin(es->wi))] += double(value) / double(kShadowRays);
        }
    }
    // The environment was picked when u_select < p_env, its sky when u.x >= p_sun (as sample_light and
    // Environment::sample choose).
    void light(const LightSample& ls, float u_select, vec2 u, vec3 added) override {
        const float c = luminance(added);
        if (!(c > 0.f) || !std::isfinite(c) || !(u_select < m_ts.environment_selection_probability())) return;
        if (u.x >= m_env.sun_probability() && m_env.pdf_sun(ls.wi) == 0.f) {
            m_tally.sky += double(c);
            m_records.push_back(SkyRecord{m_p, ls.wi, c * c, m_env.pdf_sky(ls.wi)});
        } else {
            m_tally.sun += double(c);
        }
    }

private:
    const TraceableScene& m_ts;
    const Environment& m_env;
    const SkyGuideGrid& m_grid;
    Pcg32& m_rng;
    std::vector<double>& m_h;
    PathTally& m_tally;
    std::vector<SkyRecord>& m_records;
    vec3 m_p{0.f};  // the vertex being watched
};

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
TrainingData train_iteration(const TraceableScene& ts, const RenderSettings& settings, const Camera& camera, int gw,
                             int gh, uint64_t seed, const SkyGuideGrid& grid, bool judged) {
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
    // The walker's paths: next-event estimation without MIS when judged (the tally's NEE-only estimate), none
    // otherwise (only the observer's sky rays are wanted); independent draws of a seed of the pass's own.
    const RenderSettings walk = training_walk(settings, judged);
    const uint32_t sampler_seed = uint32_t(seed ^ (seed >> 32));
    parallel_for_range(0, chunks, [&](const tbb::blocked_range<int>& range) {
        enable_ftz_daz();
        PathWalker walker;
        Sampler sampler(sampler_seed, SamplerKind::Independent);
        for (int chunk = range.begin(); chunk != range.end(); ++chunk) {
            Chunk& part = parts[size_t(chunk)];
            for (std::vector<double>& h : part.hist) h.assign(bins, 0.0);
            for (int gy = chunk * kChunkRows; gy < std::min(gh, (chunk + 1) * kChunkRows); ++gy)
                for (int gx = 0; gx < gw; ++gx)
                    for (int s = 0; s < kPathsPerCell; ++s) {
                        const uint64_t key = hash_combine(hash_combine(seed, uint64_t(gx)), uint64_t(gy));
                        Pcg32 rng;
                        rng.seed(hash_combine(key, uint64_t(s)), key);
                        const float fx = rng.next_float(), fy = rng.next_float();
                        const float lx = rng.next_float(), ly = rng.next_float();
                        const vec2 film = (vec2(float(gx), float(gy)) + vec2(fx, fy)) * cell_size;
                        const size_t t = (size_t(gy) * size_t(gw) + size_t(gx)) * kPathsPerCell + size_t(s);
                        TrainingObserver observer(ts, grid, rng, part.hist[s], out.tally[t], part.records[s]);
                        sampler.start(uvec2(uint32_t(gx), uint32_t(gy)), uint32_t(s));
                        walker.start(ts, walk, camera.generate(film, vec2(lx, ly)), sampler);
                        walker.observe(&observer);
                        while (walker.step()) {
                        }
                        out.tally[t].y = double(luminance(walker.radiance()));
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
    const TrainingData data = train_iteration(ts, settings, camera, pilot.x, pilot.y, seed, grid, true);
    std::vector<double> weights(data.hist[0].size());
    for (size_t i = 0; i < weights.size(); ++i) weights[i] = data.hist[0][i] + data.hist[1][i];
    judge(data, SkyGuide(weights, grid), t);
    // The rest of kSkyGuideTrainingCells, where the guide will be used (not for the decision: it needs no tallies).
    const bool pays = t.variance_ratio * kSkyGuideRelativeCost < 1.0;
    const bool wanted = settings.sky_guide == SkyGuideMode::On || pays;
    const int rest = kSkyGuideTrainingCells - pilot.x * pilot.y;
    if (wanted && rest >= kSkyGuidePilotCells / 4) {
        const glm::ivec2 more = film_grid(double(rest));
        const TrainingData d2 =
            train_iteration(ts, settings, camera, more.x, more.y, hash_combine(seed, 2), grid, false);
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

void SkyGuideLifecycle::restart(TraceableScene& ts, const RenderSettings& settings, uint64_t version) {
    m_seconds = 0.0;
    if (m_keep && m_decided && settings == m_settings && version == m_version) return;
    ts.set_sky_guide(nullptr);
    m_due = settings.sky_guide != SkyGuideMode::Off;
    m_decided = false;
    m_used = false;
    m_variance_ratio = 1.0;
    m_settings = settings;
    m_pending_version = version;
}

void SkyGuideLifecycle::train_if_due(TraceableScene& ts, const RenderSettings& settings, const Camera& camera) {
    if (!m_due) return;
    const auto start = std::chrono::steady_clock::now();
    m_due = false;
    SkyGuideTraining t = train_sky_guide_judged(ts, settings, camera);
    if (t.guide) m_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    m_variance_ratio = t.variance_ratio;
    if (settings.sky_guide == SkyGuideMode::Auto && !t.use) t.guide = nullptr;
    m_used = t.guide != nullptr;
    ts.set_sky_guide(std::move(t.guide));
    m_decided = true;
    m_settings = settings;
    m_version = m_pending_version;
}

RenderSettings SkyGuideLifecycle::as_rendered(const TraceableScene& ts, const RenderSettings& settings) const {
    RenderSettings s = settings;
    if (!sky_guide_applies(ts, settings))
        s.sky_guide = SkyGuideMode::Off;
    else if (s.sky_guide == SkyGuideMode::Auto && !m_due)  // decided: on only where the guide is used
        s.sky_guide = ts.sky_guide() ? SkyGuideMode::On : SkyGuideMode::Off;
    return s;
}

std::string SkyGuideLifecycle::status(const TraceableScene& ts, const RenderSettings& settings) const {
    if (settings.sky_guide == SkyGuideMode::Off) return "";
    if (!sky_guide_applies(ts, settings)) return "not applicable";
    if (m_due) return "training in the first pass";
    const char* state = ts.sky_guide() ? "on" : "off";
    if (settings.sky_guide != SkyGuideMode::Auto) return state;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s (auto: variance x%.2f predicted)", state, m_variance_ratio);
    return buf;
}

}  // namespace pv
