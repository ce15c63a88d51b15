// core/frame/renderer.cpp: tiles on a TBB arena; counters are per tile, added once per tile (no shared cache
// lines in the hot loop).
#include "core/frame/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstdio>

#include "core/base/error.h"
#include "core/base/parallel.h"
#include "core/base/text.h"
#include "core/base/tsan.h"

namespace pv {

namespace {
constexpr int kTile = 16;

}  // namespace

// A tile's counters (summed once per tile: no shared cache lines in the hot loop).
struct alignas(64) Renderer::TileTotals {
    PathCounters counters;
    uint64_t dropped = 0;
};

namespace {
Renderer::TileTotals totals_sum(const std::vector<Renderer::TileTotals>& totals) {
    Renderer::TileTotals sum;
    for (const Renderer::TileTotals& tt : totals) {
        sum.counters += tt.counters;
        sum.dropped += tt.dropped;
    }
    return sum;
}
}  // namespace

struct Renderer::Pool {
    tbb::task_arena arena;
    explicit Pool(int threads) : arena(threads) {}
};

Renderer::Renderer(std::shared_ptr<const Scene> scene, int threads, const std::function<void(double)>& build_progress) {
    m_threads = threads > 0 ? threads : usable_cores();
    m_pool = std::make_unique<Pool>(m_threads);
    m_pool->arena.execute([&] { m_traceable = std::make_unique<TraceableScene>(std::move(scene), build_progress); });
    m_camera = Camera(m_traceable->scene().camera, 64, 64);
    m_paths_in_flight = default_paths_in_flight(*m_traceable);
}

int default_paths_in_flight(const TraceableScene& ts) {
    const Scene& s = ts.scene();
    size_t bytes = ts.accel().stats().bytes;
    if (ts.triangle_record(0)) bytes += s.triangles.size() * sizeof(TriangleRecord);
    for (const Texture& t : s.textures) bytes += t.bytes();
    return bytes > kInterleaveBytes ? 4 : 1;
}

Renderer::~Renderer() = default;

void Renderer::set_materials(const std::vector<Material>& materials) {
    m_pool->arena.execute([&] { m_traceable->set_materials(materials); });  // a BVH rebuild runs on our threads
    ++m_scene_version;
}

void Renderer::restart(const CameraDesc& camera, const RenderSettings& settings, int width, int height) {
    // Checked before anything changes: a refused restart leaves the renderer as it was.
    PixelRect region{0, 0, width, height};
    if (m_region_next) {
        const PixelRect& r = *m_region_next;
        region = PixelRect{std::clamp(r.x0, 0, width), std::clamp(r.y0, 0, height), std::clamp(r.x1, 0, width),
                           std::clamp(r.y1, 0, height)};
        if (region != PixelRect{0, 0, width, height} && (m_adaptive_next.enabled() || m_adaptive_next.allocate))
            throw Error("a render region cannot be combined with adaptive sampling");
    }
    m_region = region;
    m_camera = Camera(camera, width, height);
    m_settings = settings;
    m_traceable->set_light_sampler(settings.light_sampler);  // the tree is built on first use (not timed)
    m_film.reset(width, height);
    m_adaptive = m_adaptive_next;
    m_mask.reset(width, height);
    // Allocation: the pilot and main films, which m_film combines (core/frame/adaptive.h); nothing without it.
    m_pilot.reset(m_adaptive.allocate ? width : 0, m_adaptive.allocate ? height : 0);
    m_main.reset(m_adaptive.allocate ? width : 0, m_adaptive.allocate ? height : 0);
    const int groups = m_light_groups_next ? m_traceable->light_groups().count() : 0;
    for (Film* f : {&m_film, &m_pilot, &m_main}) f->set_groups(groups);
    m_main_passes = 0;
    m_stats = RenderStats{};
    m_next_sample = 0;
    m_guide.restart(*m_traceable, settings, m_scene_version);  // kept with set_keep_sky_guide, else trained again
    m_stats.guide_used = m_guide.used();
    m_stats.guide_variance_ratio = m_guide.variance_ratio();
}

void Renderer::load_film(Film film) {
    if (film.width() != m_film.width() || film.height() != m_film.height())
        throw Error("a film of " + std::to_string(film.width()) + "x" + std::to_string(film.height()) +
                    " does not fit a render of " + std::to_string(m_film.width()) + "x" +
                    std::to_string(m_film.height()));
    if (m_adaptive.allocate)
        throw Error("a film cannot be loaded into a render with adaptive sampling (its samples are not per index)");
    m_film = std::move(film);
}

namespace {

// A path in flight on a render thread (PathWalker), with its own sampler (Sampler::start resets it per sample).
struct Slot {
    PathWalker walker;
    Sampler sampler;
    int x = 0, y = 0;
    uint32_t sample = 0;
    bool busy = false;
};

// One pass: what every tile reads, and the tile's work.
struct PassJob {
    const TraceableScene& ts;
    const RenderSettings& settings;
    const Camera& camera;
    Film& film;             // m_film, or with allocation the pilot or main film
    AdaptiveMask& mask;     // with allocation, the pixels' sample indices
    const uint8_t* active;  // adaptive sampling's mask (nothing: every pixel)
    PixelRect region;
    int w, tiles_x;
    uint32_t index;             // the pass's sample index (without allocation)
    uint32_t first_sample;      // the accumulation's first index (with it)
    const LightGroups* groups;  // the film's light groups (nullptr: none)
    bool own_index, pilot;
    int in_flight;

    // The tile's pixels in scan order, each path in one of `in_flight` slots, the slots advanced in turn
    // (PathWalker::step) and each refilled with the next pixel as its path ends. A pixel takes one sample per pass,
    // so its film sums see the same values in the same order whatever the interleaving.
    void render_tile(int tile, Slot* slots, Renderer::TileTotals& tt) const {
        // The tile clipped to the region (the whole image without one: the tiles as they always were).
        const int x0 = std::max((tile % tiles_x) * kTile, region.x0);
        const int y0 = std::max((tile / tiles_x) * kTile, region.y0);
        const int x1 = std::min({(tile % tiles_x) * kTile + kTile, w, region.x1});
        const int y1 = std::min({(tile / tiles_x) * kTile + kTile, film.height(), region.y1});
        if (x1 <= x0 || y1 <= y0) return;
        const int tile_w = x1 - x0, tile_pixels = tile_w * (y1 - y0);
        int next = 0;
        auto start_next = [&](Slot& s) {
            while (next < tile_pixels) {
                const int x = x0 + next % tile_w, y = y0 + next / tile_w;
                ++next;
                if (active && !active[size_t(y) * size_t(w) + size_t(x)]) continue;
                film.prefetch(x, y);
                s.x = x;
                s.y = y;
                s.sample = !own_index ? index
                           : pilot    ? first_sample + mask.pilot_index(x, y)++
                                      : first_sample + mask.next_index(x, y)++;
                s.walker.start(ts, settings, camera_ray(camera, s.sampler, x, y, s.sample), s.sampler);
                if (groups) [[unlikely]]
                    s.walker.group_by(groups);
                return s.busy = true;
            }
            return s.busy = false;
        };
        int busy = 0;
        for (int i = 0; i < in_flight; ++i) busy += start_next(slots[i]) ? 1 : 0;
        while (busy > 0)
            for (int i = 0; i < in_flight; ++i) {
                Slot& s = slots[i];
                if (!s.busy || s.walker.step()) continue;
                const PathCounters& c = s.walker.counters();
                tt.counters += c;
                if (pilot) mask.add_rays(s.x, s.y, c.rays + c.shadow_rays);
                const bool added = groups ? film.add(s.x, s.y, s.sample, s.walker.radiance(), s.walker.group_radiance())
                                          : film.add(s.x, s.y, s.sample, s.walker.radiance());
                if (!added) tt.dropped++;
                if (!start_next(s)) --busy;
            }
    }
};

}  // namespace

bool Renderer::render_pass(const std::atomic<bool>* cancel) {
    const auto start = std::chrono::steady_clock::now();
    if (m_guide.due()) {
        m_pool->arena.execute([&] { m_guide.train_if_due(*m_traceable, m_settings, m_camera); });
        m_stats.guide_seconds = m_guide.seconds();
        m_stats.guide_used = m_guide.used();
        m_stats.guide_variance_ratio = m_guide.variance_ratio();
    }
    if (m_stats.spp == 0) m_first_sample = m_next_sample;
    // Allocation: pixels take the samples of their own count (core/frame/adaptive.h), in a pilot pass under the pilot
    // seed into the pilot film, otherwise into the main film; without it, the pass's index into m_film.
    const bool own_index = m_adaptive.allocate;
    const bool pilot = own_index && is_pilot_pass(m_stats.spp + 1);
    if (own_index) m_mask.prepare_pass(pilot, m_main_passes + 1);
    const int w = m_film.width(), h = m_film.height();
    const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
    // The groups as the film keeps them (an edit since the restart that changed their count: none until the next).
    const LightGroups* groups = m_film.groups() > 0 && m_film.groups() == m_traceable->light_groups().count()
                                    ? &m_traceable->light_groups()
                                    : nullptr;
    const PassJob job{*m_traceable,     m_settings,
                      m_camera,         !own_index ? m_film : pilot ? m_pilot : m_main,
                      m_mask,           m_adaptive.masks() ? m_mask.mask().data() : nullptr,
                      m_region,         w,
                      tiles_x,          m_next_sample,
                      m_first_sample,   groups,
                      own_index,        pilot,
                      m_paths_in_flight};
    const uint32_t seed = pilot ? pilot_seed(m_settings.seed) : m_settings.seed;
    std::vector<TileTotals> totals(size_t(tiles_x) * size_t(tiles_y));
    std::atomic<bool> cancelled{false};
    const char fork_edge = 0, join_edge = 0;  // addresses for TSan's happens-before edges (core/base/tsan.h)
    tsan_release(&fork_edge);
    m_pool->arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y, 1), [&](const tbb::blocked_range<int>& r) {
            const TsanTaskScope tsan_scope(&fork_edge, &join_edge);
            enable_ftz_daz();
            Slot slots[kMaxPathsInFlight];
            for (int i = 0; i < job.in_flight; ++i) slots[i].sampler = Sampler(seed, m_settings.sampler);
            for (int tile = r.begin(); tile != r.end(); ++tile) {
                if (cancel && cancel->load(std::memory_order_relaxed)) {
                    cancelled.store(true, std::memory_order_relaxed);
                    return;
                }
                job.render_tile(tile, slots, totals[size_t(tile)]);
            }
        });
    });
    tsan_acquire(&join_edge);
    if (cancelled.load()) return false;
    finish_pass(totals_sum(totals), pilot, start);
    return true;
}

void Renderer::finish_pass(const TileTotals& totals, bool pilot, std::chrono::steady_clock::time_point start) {
    m_stats.rays += totals.counters.rays;
    m_stats.shadow_rays += totals.counters.shadow_rays;
    m_stats.paths += totals.counters.paths;
    m_stats.vertices += totals.counters.vertices;
    m_stats.dropped += totals.dropped;
    m_stats.spp++;
    m_next_sample++;
    if (m_adaptive.allocate) {
        if (pilot)
            m_mask.update_weights(gains_identity(m_gains) ? m_pilot : m_pilot.mixed(m_gains), m_adaptive);
        else
            ++m_main_passes;
        m_mask.combine(m_pilot, m_main, m_film);
    }
    // Adaptive sampling measures the image as mixed (the film itself without gains).
    if (gains_identity(m_gains) || !m_adaptive.enabled())
        m_mask.update(m_film, m_stats.spp, m_adaptive);
    else
        m_mask.update(mixed_film(), m_stats.spp, m_adaptive);
    m_stats.last_pass_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    m_stats.seconds += m_stats.last_pass_seconds;
}

Metadata render_metadata(const Renderer& r) {
    const RenderStats& st = r.stats();
    const CameraDesc& c = r.camera().desc();
    auto v3 = [](vec3 v) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g", v.x, v.y, v.z);
        return std::string(buf);
    };
    Metadata m;
    m["pathview:spp"] = std::to_string(st.spp);
    m["pathview:seconds"] = std::to_string(st.seconds);
    m["pathview:settings"] = r.settings_as_rendered().describe();
    m["pathview:camera"] = "--eye " + v3(c.eye) + " --target " + v3(c.target) + " --up " + v3(c.up) + " --fov " +
                           std::to_string(c.vfov_deg) + " --aperture " + std::to_string(c.aperture) +
                           " --focus-distance " + std::to_string(c.focus_distance);
    m["pathview:dropped_samples"] = std::to_string(st.dropped);
    // The film's reference-free relMSE estimate of the mean image (even/odd half buffers, eps 0.01).
    char est[32];
    std::snprintf(est, sizeof est, "%.6g", r.film().estimated_rel_mse());
    m["pathview:est_relmse"] = est;
    m["pathview:rays"] = std::to_string(st.rays + st.shadow_rays);
    m["pathview:scene"] = r.scene().source;
    m["pathview:threads"] = std::to_string(r.threads());
    if (r.has_region()) m["pathview:region"] = format_region(r.region());
    if (r.adaptive_settings().enabled()) {
        m["pathview:noise_threshold"] = std::to_string(r.adaptive_settings().noise_threshold);
        m["pathview:min_spp"] = std::to_string(r.adaptive_settings().min_spp);
        m["pathview:active_fraction"] = std::to_string(r.adaptive_mask().active_fraction());
    }
    if (r.adaptive_settings().allocate) {
        m["pathview:adaptive"] = "on";
        m["pathview:min_spp"] = std::to_string(r.adaptive_settings().min_spp);
        m["pathview:mean_spp"] = std::to_string(r.film().mean_count());
    }
    return m;
}

std::string format_region(const PixelRect& r) {
    return std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) + "," + std::to_string(r.y1);
}

PixelRect parse_region(const std::string& text, int width, int height, const std::string& what) {
    const std::string shown = what + " " + quote_prefix(text);
    int v[4] = {0, 0, 0, 0};
    size_t pos = 0;
    for (int i = 0; i < 4; ++i) {
        const size_t end = i < 3 ? text.find(',', pos) : text.size();
        if (end == std::string::npos) throw Error(shown + ": expected x0,y0,x1,y1 (four integers)");
        const std::optional<uint64_t> n = parse_decimal(text.substr(pos, end - pos), 1u << 30);
        if (!n) throw Error(shown + ": expected x0,y0,x1,y1 (four non-negative integers)");
        v[i] = int(*n);
        pos = end + 1;
    }
    const PixelRect r{v[0], v[1], v[2], v[3]};
    if (r.empty()) throw Error(shown + ": the region is empty (it needs x0 < x1 and y0 < y1; x1 and y1 are excluded)");
    if (r.x1 > width || r.y1 > height)
        throw Error(shown + ": the region is not inside the " + std::to_string(width) + "x" + std::to_string(height) +
                    " image (x1 <= width, y1 <= height)");
    return r;
}

std::string format_si(double value) {
    const char* units[] = {"", " k", " M", " G", " T"};
    int u = 0;
    while (std::fabs(value) >= 1000.0 && u < 4) {
        value /= 1000.0;
        ++u;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g%s", value, units[u]);
    return buf;
}

}  // namespace pv
