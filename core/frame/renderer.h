// core/frame/renderer.h: progressive rendering. One pass adds one sample to every pixel, rendered in tiles on a
// TBB arena of `threads` workers. Random numbers depend only on (pixel, sample index, seed): the image is
// bit-identical for any thread count. A pass can be cancelled from another thread; restart() then clears
// the film, so a cancelled pass never leaves samples behind.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "core/frame/adaptive.h"
#include "core/image/film.h"
#include "core/image/image_io.h"
#include "core/render/integrator.h"
#include "core/render/sky_guide_training.h"
#include "core/render/traceable_scene.h"
#include "core/scene/camera.h"

namespace pv {

struct RenderStats {
    uint32_t spp = 0;      // completed passes since restart
    double seconds = 0.0;  // time spent in completed passes
    uint64_t rays = 0;     // closest-hit rays
    uint64_t shadow_rays = 0;
    uint64_t paths = 0;
    uint64_t vertices = 0;
    uint64_t dropped = 0;  // non-finite or negative samples dropped
    double last_pass_seconds = 0.0;
    double guide_seconds = 0.0;         // the sky guide's training, inside the first pass's time (0: none trained)
    bool guide_used = false;            // the trained guide samples the sky (--sky-guide on, or auto's decision)
    double guide_variance_ratio = 1.0;  // the training's prediction (SkyGuideTraining::variance_ratio)
};

// A render region: the pixels x0 <= x < x1, y0 <= y < y1 of the image (half-open, from the top-left).
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    bool operator==(const PixelRect& o) const { return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1; }
    bool operator!=(const PixelRect& o) const { return !(*this == o); }
};
// "x0,y0,x1,y1".
std::string format_region(const PixelRect& r);
// Parses "x0,y0,x1,y1" (four non-negative integers) and checks it against a width x height image: throws pv::Error
// naming `what` when malformed, empty or not inside the image.
PixelRect parse_region(const std::string& text, int width, int height, const std::string& what);

class Renderer {
public:
    // Prepares `scene` for tracing (TraceableScene: the BVH, built on the render threads, throws pv::Error on
    // failure; build_progress: see Accel). threads = 0: all cores.
    Renderer(std::shared_ptr<const Scene> scene, int threads = 0,
             const std::function<void(double)>& build_progress = {});
    ~Renderer();

    // Sets camera, estimator and resolution, and clears the film. Not concurrent with render_pass(); nor are
    // set_materials (same count as the scene's; the BVH is kept) and set_environment (see TraceableScene), which
    // take effect from the next pass.
    void restart(const CameraDesc& camera, const RenderSettings& settings, int width, int height);
    void set_materials(const std::vector<Material>& materials);
    void set_environment(const EnvironmentSettings& settings) {
        m_traceable->set_environment(settings);
        ++m_scene_version;
    }
    // The global medium, as set_environment (the viewer's fog controls).
    void set_fog(const HomogeneousMedium& fog) {
        m_traceable->set_fog(fog);
        ++m_scene_version;
    }
    // The viewer: a restart that changes only the camera or the image size keeps the trained sky guide and auto's
    // decision (any guide leaves the estimator unbiased; retraining at every camera move would delay each first
    // pass while the user orbits). New settings, materials or environment retrain. Off by default: a render's
    // guide then depends only on its own camera, settings and scene.
    void set_keep_sky_guide(bool keep) { m_guide.set_keep(keep); }

    // Passes from now on render sample indices first, first + 1, ... (restart() starts at 0), so that a render
    // can be split into sample ranges and merged (core/partial/partial.h). Not concurrent with render_pass().
    void set_next_sample(uint32_t first) { m_next_sample = first; }
    uint32_t next_sample() const { return m_next_sample; }
    // Replaces the film's accumulators with `film` (the current size; e.g. a partial render being resumed).
    void load_film(Film film);

    // A render region for the accumulations that follow (takes effect at the next restart(), clamped to the image
    // there; nothing: the whole image). Every sample of a pass lands inside it; pixels outside keep no samples.
    // Inside, a pixel takes exactly the samples a full render gives it (they depend on pixel and index only), so
    // its value equals the full render's bit for bit. Not with adaptive sampling (restart() throws pv::Error).
    void set_region(std::optional<PixelRect> region) { m_region_next = region; }
    // The region in use: the whole image without one.
    const PixelRect& region() const { return m_region; }
    bool has_region() const { return m_region != PixelRect{0, 0, m_film.width(), m_film.height()}; }

    // Adaptive sampling (core/frame/adaptive.h) for the accumulations that follow: takes effect at the next restart().
    void set_adaptive(const AdaptiveSettings& adaptive) { m_adaptive_next = adaptive; }
    const AdaptiveSettings& adaptive_settings() const { return m_adaptive; }
    // Which pixels still take samples (all of them without adaptive sampling).
    const AdaptiveMask& adaptive_mask() const { return m_mask; }
    // True once adaptive sampling has stopped every pixel: further passes add nothing.
    bool converged() const { return m_adaptive.enabled() && m_mask.converged(); }

    // Adds one sample per pixel (per active pixel with adaptive sampling). Returns false if `cancel` became true during
    // the pass (the film then holds a partial pass: call restart() before using it).
    bool render_pass(const std::atomic<bool>* cancel = nullptr);

    const Film& film() const { return m_film; }

    // Light groups (core/render/light_groups.h, docs/light-groups.md): with them on, from the next restart() the
    // film keeps each group's sums beside the image's (when the scene has more than one group; the image is the
    // same, bit for bit). Off by default: no memory, no cost.
    void set_light_groups(bool on) { m_light_groups_next = on; }
    // The groups the film keeps (0: none).
    int light_group_count() const { return m_film.groups(); }
    // Gains per group for the mixed image (Film::mixed); adaptive sampling then measures the mix. Any time between
    // passes; no restart.
    void set_light_gains(LightGains gains) { m_gains = std::move(gains); }
    const LightGains& light_gains() const { return m_gains; }
    // The film of the image as mixed with the gains (the film itself with every gain 1).
    Film mixed_film() const { return m_film.mixed(m_gains); }
    // With allocation, the pilot and main samples' own films (empty without it).
    const Film& pilot_film() const { return m_pilot; }
    const Film& main_film() const { return m_main; }
    const RenderStats& stats() const { return m_stats; }
    const RenderSettings& settings() const { return m_settings; }
    // The settings with sky_guide on only where the guide applies (sky_guide_applies) and, for auto, once the first
    // pass decided, where it is used (auto until then): what the image depends on, for metadata and partial renders
    // (a render the guide cannot change keeps the string it had before it).
    RenderSettings settings_as_rendered() const { return m_guide.as_rendered(*m_traceable, m_settings); }
    // What the sky guide does in this accumulation, for the viewer: "" with --sky-guide off, else "not applicable",
    // "training in the first pass", or "on" / "off", with the pilot's predicted variance ratio for auto.
    std::string sky_guide_status() const { return m_guide.status(*m_traceable, m_settings); }
    const Camera& camera() const { return m_camera; }
    const Scene& scene() const { return m_traceable->scene(); }
    // The scene as traced: current materials and environment, BVH, lights.
    const TraceableScene& traceable() const { return *m_traceable; }
    int threads() const { return m_threads; }

    // Paths each render thread interleaves (PathWalker): while one waits for its hit record or texels, the thread
    // advances the others. Chosen at construction by default_paths_in_flight; any count gives the same image, bit
    // for bit. Not concurrent with render_pass().
    static constexpr int kMaxPathsInFlight = 8;
    void set_paths_in_flight(int n) { m_paths_in_flight = std::clamp(n, 1, kMaxPathsInFlight); }
    int paths_in_flight() const { return m_paths_in_flight; }

    struct TileTotals;  // a tile's counters (renderer.cpp)

private:
    // The pass's bookkeeping once its tiles are done: counters, sample index, adaptive sampling, time.
    void finish_pass(const TileTotals& totals, bool pilot, std::chrono::steady_clock::time_point start);
    std::unique_ptr<TraceableScene> m_traceable;
    RenderSettings m_settings;
    Camera m_camera;
    Film m_film;           // the image's accumulation (with allocation: m_pilot and m_main combined)
    Film m_pilot, m_main;  // allocation: the pilot and main samples (core/frame/adaptive.h); 0x0 without it
    bool m_light_groups_next = false;
    LightGains m_gains;
    uint32_t m_main_passes = 0;
    AdaptiveSettings m_adaptive, m_adaptive_next;
    AdaptiveMask m_mask;
    std::optional<PixelRect> m_region_next;
    PixelRect m_region;
    RenderStats m_stats;
    uint32_t m_next_sample = 0;
    uint32_t m_first_sample = 0;   // m_next_sample at the accumulation's first pass
    SkyGuideLifecycle m_guide;     // the sky guide's training and retraining (core/render/sky_guide_training.h)
    uint64_t m_scene_version = 0;  // counts set_materials / set_environment calls
    int m_threads = 1;
    int m_paths_in_flight = 1;
    struct Pool;
    std::unique_ptr<Pool> m_pool;
};

// 4 paths in flight per thread where the hit data (the BVH, the packed hit records and the texels) takes more than
// kInterleaveBytes, so that a hit's record and texels come from memory rather than from the caches; 1 (no
// interleaving, nothing to hide and the switching to pay) below. docs/ray-speed.md, sixth round.
constexpr size_t kInterleaveBytes = size_t(4) << 20;
int default_paths_in_flight(const TraceableScene& ts);

// EXR metadata describing the current accumulation: spp, seconds, settings, camera, dropped samples, scene (and
// pathview:region "x0,y0,x1,y1" with a region).
Metadata render_metadata(const Renderer& renderer);

// "12.3 M" style formatting of a rate, for summaries.
std::string format_si(double value);

}  // namespace pv
