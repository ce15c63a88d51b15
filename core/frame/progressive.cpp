// core/frame/progressive.cpp: the driver thread. Its loop: take the pending request (restart the film), render one
// pass with the cancel flag, then publish unless a newer request arrived meanwhile. restart() raises the cancel
// flag under the same mutex that the driver clears it under when it takes the request, so a pass is cancelled
// only on behalf of a request the driver has not taken yet.
#include "core/frame/progressive.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/base/error.h"
#include "core/denoise/denoise_atrous.h"
#include "core/frame/render_output.h"
#include "core/frame/renderer_partial.h"
#include "core/image/metrics.h"

namespace pv {

ProgressiveRenderer::ProgressiveRenderer(std::shared_ptr<const Scene> scene, int threads)
    : m_scene(scene), m_renderer(std::move(scene), threads) {
    m_renderer.set_keep_sky_guide(true);  // orbiting does not retrain the sky guide (Renderer::set_keep_sky_guide)
    m_renderer.set_light_groups(true);    // the panel's live mix (no memory when the scene has one group)
    m_thread = std::thread([this] { drive(); });
}

ProgressiveRenderer::~ProgressiveRenderer() {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_quit = true;
        m_cancel.store(true);
        m_nfor_cancel.store(true);
    }
    m_wake.notify_all();
    m_thread.join();
}

uint64_t ProgressiveRenderer::restart(const RenderRequest& request) {
    // Validate here, on the caller's thread: the driver thread must not meet an exception.
    if (request.width < 1 || request.height < 1) throw Error("restart: the image size must be at least 1x1");
    if (!request.materials.empty() && request.materials.size() != m_scene->materials.size())
        throw Error("restart: expected one material per scene material");
    (void)Camera(request.camera, request.width, request.height);
    if (request.region) {
        const PixelRect& r = *request.region;
        if (std::max(r.x0, 0) >= std::min(r.x1, request.width) || std::max(r.y0, 0) >= std::min(r.y1, request.height))
            throw Error("restart: the render region " + format_region(r) + " holds no pixel of the " +
                        std::to_string(request.width) + "x" + std::to_string(request.height) + " image");
        if (request.adaptive.enabled() || request.adaptive.allocate)
            throw Error("restart: a render region cannot be combined with adaptive sampling");
    }
    uint64_t generation;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_pending = request;
        generation = ++m_generation;
        m_request_posted = std::chrono::steady_clock::now();
        m_cancel.store(true);
        m_nfor_cancel.store(true);
    }
    m_wake.notify_all();
    return generation;
}

void ProgressiveRenderer::set_paused(bool paused) {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (!paused) m_nfor_cancel.store(true);
        m_paused = paused;
    }
    m_wake.notify_all();
}

void ProgressiveRenderer::set_target(uint32_t target_spp, double target_seconds) {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_target_spp = target_spp;
        m_target_seconds = std::max(0.0, target_seconds);
        m_nfor_cancel.store(true);
    }
    m_wake.notify_all();
}

void ProgressiveRenderer::set_on_publish(std::function<void()> callback) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_on_publish = std::move(callback);
}

int ProgressiveRenderer::threads() const { return m_renderer.threads(); }

void ProgressiveRenderer::set_denoise(bool on) {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (!on) m_nfor_cancel.store(true);
        m_denoise = on;
    }
    m_wake.notify_one();
}

void ProgressiveRenderer::request_partial() {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_partial_requested = true;
    }
    m_wake.notify_one();
}

std::string ProgressiveRenderer::take_partial_refusal() {
    std::lock_guard<std::mutex> lock(m_snapshot_mutex);
    return std::exchange(m_partial_refusal, std::string());
}

std::optional<PartialRender> ProgressiveRenderer::take_partial() {
    std::lock_guard<std::mutex> lock(m_snapshot_mutex);
    std::optional<PartialRender> out = std::move(m_partial);
    m_partial.reset();
    return out;
}

bool ProgressiveRenderer::latest(Snapshot& out) const {
    std::lock_guard<std::mutex> lock(m_snapshot_mutex);
    if (m_front.serial <= out.serial) return false;
    out = m_front;
    return true;
}

uint64_t ProgressiveRenderer::published_generation() const {
    std::lock_guard<std::mutex> lock(m_snapshot_mutex);
    return m_front.generation;
}

bool ProgressiveRenderer::wait_for(uint64_t generation, uint32_t min_spp, std::chrono::milliseconds timeout) const {
    std::unique_lock<std::mutex> lock(m_snapshot_mutex);
    return m_published.wait_for(lock, timeout, [&] {
        return m_front.generation > generation || (m_front.generation == generation && m_front.spp >= min_spp);
    });
}

std::optional<PickResult> ProgressiveRenderer::pick(const CameraDesc& camera, int width, int height,
                                                    vec2 film_px) const {
    // The Camera and the BVH query are local: the driver's Renderer state is not touched.
    const Camera cam(camera, std::max(width, 1), std::max(height, 1));
    return m_renderer.traceable().pick(cam, film_px);
}

bool ProgressiveRenderer::target_reached() const {
    const RenderStats& st = m_renderer.stats();
    return (m_target_spp > 0 && st.spp >= m_target_spp) || (m_target_seconds > 0.0 && st.seconds >= m_target_seconds) ||
           m_renderer.converged();
}

bool ProgressiveRenderer::partial_due() const { return m_partial_requested && m_renderer.stats().spp > 0; }

bool ProgressiveRenderer::denoise_due() const {
    // m_denoised_* are the driver's own; this runs on the driver thread.
    return m_denoise && m_renderer.stats().spp > 0 &&
           (m_denoised_generation != m_generation || m_denoised_spp != m_renderer.stats().spp);
}

bool ProgressiveRenderer::nfor_due() const {
    const uint32_t spp = m_renderer.stats().spp;
    return m_denoise && !should_render() && spp >= kNforMinSpp && !denoise_due() &&
           (m_nfor_generation != m_generation || m_nfor_spp != spp);
}

bool ProgressiveRenderer::should_render() const {
    // A new accumulation gets its first pass even while paused, so the picture follows the camera.
    return !target_reached() && (!m_paused || m_renderer.stats().spp == 0);
}

void ProgressiveRenderer::drive() {
    enable_ftz_daz();
    bool has_request = false;
    uint64_t generation = 0;
    RenderRequest request;
    for (;;) {
        bool is_new = false, make_partial = false;
        std::optional<LightGains> gains;
        {
            std::unique_lock<std::mutex> lock(m_mutex);
            m_wake.wait(lock, [&] {
                return m_quit || m_pending ||
                       (has_request && (should_render() || partial_due() || m_gains_pending ||
                                        ((denoise_due() || nfor_due()) && !m_pending)));
            });
            if (m_quit) return;
            if (m_pending) {
                request = std::move(*m_pending);
                m_pending.reset();
                generation = m_generation;
                m_cancel.store(false);
                m_request_taken = std::chrono::steady_clock::now();
                m_wait_ms = std::chrono::duration<double>(m_request_taken - m_request_posted).count() * 1e3;
                has_request = is_new = true;
            }
            make_partial = has_request && !m_pending && m_partial_requested;
            gains = std::move(m_gains_pending);
            m_gains_pending.reset();
        }
        if (is_new) {
            if (!request.materials.empty()) m_renderer.set_materials(request.materials);
            if (request.environment) m_renderer.set_environment(*request.environment);
            if (request.fog) m_renderer.set_fog(*request.fog);
            m_renderer.set_adaptive(request.adaptive);
            m_renderer.set_region(request.region);
            m_renderer.restart(request.camera, request.settings, request.width, request.height);
            m_error_history.clear();
        }
        if (gains) {
            // A new mix: the film as it is, re-published (and denoised again) without a pass.
            m_renderer.set_light_gains(std::move(*gains));
            m_denoised_generation = 0;
            m_nfor_generation = 0;
            if (!is_new && m_renderer.stats().spp > 0) {
                bool reached;
                {
                    std::lock_guard<std::mutex> lock(m_mutex);
                    reached = target_reached();
                }
                publish(generation, reached, /*force_denoise=*/true);
            }
        }
        // Between passes the film holds whole passes only; a new accumulation gets its first pass first.
        if (make_partial && m_renderer.stats().spp > 0) {
            const uint32_t spp = m_renderer.stats().spp;
            const bool region = m_renderer.has_region();
            const bool refused = m_renderer.adaptive_settings().allocate || region;
            std::optional<PartialRender> part;
            if (!refused) part = partial_from_renderer(m_renderer, {{m_renderer.next_sample() - spp, spp}});
            std::function<void()> on_publish;
            {
                std::lock_guard<std::mutex> lock(m_mutex);
                m_partial_requested = false;
                on_publish = m_on_publish;
            }
            {
                std::lock_guard<std::mutex> lock(m_snapshot_mutex);
                m_partial = std::move(part);
                if (region)
                    m_partial_refusal =
                        "no resumable snapshot of a render region (partial renders cover the whole image): clear the "
                        "region to make one";
                else if (refused)
                    m_partial_refusal =
                        "no resumable snapshot with adaptive sampling on (its samples are not per index): "
                        "turn it off to make one";
            }
            if (on_publish) on_publish();
        }
        bool idle_denoise = false, idle_nfor = false;
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            if (m_quit || m_pending || !has_request) continue;
            if (!should_render()) {
                // Stopped (paused, target reached): denoise the film as it is, once, if asked to: the a-trous
                // image at once, then NFOR's.
                idle_denoise = denoise_due() && generation == m_generation;
                idle_nfor = !idle_denoise && nfor_due() && generation == m_generation;
                if (idle_nfor) m_nfor_cancel.store(false);  // under the lock the events that cancel it take
                if (!idle_denoise && !idle_nfor) continue;
            }
        }
        if (idle_nfor) {
            run_nfor(generation);
            continue;
        }
        if (idle_denoise) {
            bool reached;
            {
                std::lock_guard<std::mutex> lock(m_mutex);
                reached = target_reached();
            }
            publish(generation, reached, /*force_denoise=*/true);
            continue;
        }
        // A cancelled pass leaves a partial film; the pending request restarts it before anything is published.
        if (!m_renderer.render_pass(&m_cancel)) continue;
        bool reached;
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            if (m_pending || m_quit) continue;  // superseded: never publish an accumulation nobody asked for
            reached = target_reached();
        }
        publish(generation, reached);
    }
}

double ProgressiveRenderer::seconds_to_threshold(float threshold) const {
    // The worst active pixel's filtered relative MSE e at n samples falls as n^b, with b fitted log-log over the last
    // four checkpoints (clamped to [-2, -0.5]; -1, the Monte Carlo rate, until there are two): it reaches
    // threshold^2 after n (e / threshold^2)^(1/-b) samples, at the current pass time (passes get cheaper as pixels
    // stop, so this errs long).
    const RenderStats& st = m_renderer.stats();
    const double e = m_renderer.adaptive_mask().worst_rel_mse(), limit = double(threshold) * double(threshold);
    if (!(e > 0.0) || !std::isfinite(e) || st.spp == 0) return -1.0;
    if (e <= limit) return 0.0;
    double slope = -1.0;
    const size_t n = m_error_history.size();
    if (n >= 2) {
        std::vector<double> spp, err;
        for (size_t i = n > 4 ? n - 4 : 0; i < n; ++i) {
            spp.push_back(m_error_history[i].first);
            err.push_back(m_error_history[i].second);
        }
        slope = std::clamp(fit_loglog(spp, err).slope, -2.0, -0.5);
    }
    const double passes = double(st.spp) * (std::pow(e / limit, -1.0 / slope) - 1.0);
    return passes * st.last_pass_seconds;
}

void ProgressiveRenderer::update_denoised(uint64_t generation, bool force) {
    bool on;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        on = m_denoise;
    }
    if (!on) {
        m_denoised_image.rgb.clear();
        m_denoised_generation = 0;
        return;
    }
    const Film& film = shown_film();
    const uint32_t spp = m_renderer.stats().spp;
    const auto now = std::chrono::steady_clock::now();
    // At most a third of the driver's time goes to the filter while rendering; always when stopped or forced.
    const bool stale = m_denoised_generation != generation;
    const bool due =
        force || stale || std::chrono::duration<double>(now - m_denoise_end).count() >= 2.0 * m_denoise_seconds;
    if (!due || (m_denoised_generation == generation && m_denoised_spp == spp)) return;
    // The features of a new accumulation take one sample per pixel, so the first frame after a camera move waits
    // for a quarter of the feature pass (it took as long as the pass itself); from the second pass on, the filter
    // gets features of kFeatureSamples, which smooth its edges.
    constexpr int kFirstFeatureSamples = 1, kFeatureSamples = 4;
    const bool new_features =
        m_features_generation != generation || m_features_width != film.width() || m_features_height != film.height();
    if (new_features || (m_features_samples < kFeatureSamples && spp >= 2)) {
        // The filter lays the features out in its own planes; the image itself is not kept.
        const auto features_start = std::chrono::steady_clock::now();
        const int samples = new_features && spp < 2 ? kFirstFeatureSamples : kFeatureSamples;
        FeatureImage features = render_features(m_renderer.traceable(), m_renderer.camera(), film.width(),
                                                film.height(), samples, m_renderer.settings().seed, &m_cancel);
        // A newer request cancels the feature pass (the filter at full resolution made the next camera move wait
        // for it); the snapshot is then not published at all.
        if (m_cancel.load()) return;
        m_atrous.set_features(std::move(features));
        m_features_samples = samples;
        m_features_generation = generation;
        m_features_width = film.width();
        m_features_height = film.height();
        m_features_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - features_start).count();
    }
    // The filter's own time sets the throttle: the feature pass above runs once per generation, and counting it
    // made the second pass of every accumulation (each coarse pass while orbiting) go undenoised.
    const auto filter_start = std::chrono::steady_clock::now();
    m_atrous.denoise(film.mean(), atrous_variance(film), m_denoised_image);
    m_denoised_nfor = false;
    m_denoised_generation = generation;
    m_denoised_spp = spp;
    m_denoise_end = std::chrono::steady_clock::now();
    m_denoise_seconds = std::chrono::duration<double>(m_denoise_end - filter_start).count();
}

void ProgressiveRenderer::run_nfor(uint64_t generation) {
    const Film& film = shown_film();
    const uint32_t spp = m_renderer.stats().spp;
    const auto start = std::chrono::steady_clock::now();
    // The features and the filter of `pathview render --denoise` (core/frame/render_output.h): what it would write.
    const FeatureImage features = camera_features(m_renderer, &m_nfor_cancel);
    if (m_nfor_cancel.load()) return;
    Image image = denoise_film(film, features, Denoiser::Nfor, nullptr, &m_nfor_cancel);
    if (m_nfor_cancel.load() || image.width == 0) return;
    m_denoised_image = std::move(image);
    m_denoised_nfor = true;
    m_denoised_generation = m_nfor_generation = generation;
    m_denoised_spp = m_nfor_spp = spp;
    m_nfor_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    bool reached;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (m_pending || m_quit || generation != m_generation) return;
        reached = target_reached();
    }
    publish(generation, reached);
}

const Film& ProgressiveRenderer::shown_film() {
    if (gains_identity(m_renderer.light_gains())) return m_renderer.film();
    m_renderer.film().mixed_into(m_renderer.light_gains(), m_mixed);
    return m_mixed;
}

void ProgressiveRenderer::set_light_gains(LightGains gains) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_gains_pending = std::move(gains);
    m_nfor_cancel.store(true);
    m_wake.notify_all();
}

void ProgressiveRenderer::publish(uint64_t generation, bool target_reached, bool force_denoise) {
    update_denoised(generation, force_denoise || target_reached);
    if (m_cancel.load()) return;  // superseded meanwhile: the driver takes the new request next
    // Fill the back buffer outside any lock, then swap it in: the UI's copy never waits for this loop.
    const Film& film = shown_film();
    const RenderStats& st = m_renderer.stats();
    Snapshot& s = m_back;
    s.generation = generation;
    s.width = film.width();
    s.height = film.height();
    s.rel_mse = film.views_into(s.rgb, s.rel_error, s.samples);
    s.spp = st.spp;
    s.seconds = st.seconds;
    s.rays = st.rays + st.shadow_rays;
    s.paths = st.paths;
    s.dropped = st.dropped;
    s.mrays_per_s = st.seconds > 0.0 ? double(s.rays) / st.seconds * 1e-6 : 0.0;
    s.ms_per_pass = st.last_pass_seconds * 1e3;
    s.target_reached = target_reached;
    s.sky_guide = m_renderer.sky_guide_status();
    s.region = m_renderer.region();
    s.light_groups.clear();
    if (m_renderer.light_group_count() > 0) s.light_groups = m_renderer.traceable().light_groups().names;
    s.active_fraction = 1.0;
    s.seconds_to_threshold = -1.0;
    if (const AdaptiveSettings& a = m_renderer.adaptive_settings(); a.enabled()) {
        const AdaptiveMask& mask = m_renderer.adaptive_mask();
        s.active_fraction = mask.active_fraction();
        if (is_adaptive_checkpoint(st.spp) && st.spp >= a.min_spp && mask.worst_rel_mse() > 0.0)
            m_error_history.emplace_back(double(st.spp), mask.worst_rel_mse());
        s.seconds_to_threshold = mask.converged() ? 0.0 : seconds_to_threshold(a.noise_threshold);
    }
    if (!m_denoised_image.rgb.empty() && m_denoised_generation == generation) {
        s.denoised = m_denoised_image.rgb;
        s.denoised_spp = m_denoised_spp;
        s.denoise_ms = (m_denoised_nfor ? m_nfor_seconds : m_denoise_seconds) * 1e3;
        s.denoised_nfor = m_denoised_nfor;
    } else {
        s.denoised.clear();
        s.denoised_spp = 0;
        s.denoise_ms = 0.0;
        s.denoised_nfor = false;
    }
    s.camera = m_renderer.camera().desc();
    s.settings = m_renderer.settings();
    s.metadata = render_metadata(m_renderer);
    if (m_first_generation != generation) {  // the accumulation's first publication
        m_first_generation = generation;
        m_first_ready_ms =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - m_request_taken).count() * 1e3;
        m_first_features_ms = m_features_generation == generation ? m_features_seconds * 1e3 : 0.0;
    }
    s.first_ready_ms = m_first_ready_ms;
    s.features_ms = m_first_features_ms;
    s.wait_ms = m_wait_ms;

    std::function<void()> on_publish;
    {
        std::lock_guard<std::mutex> lock(m_snapshot_mutex);
        s.serial = m_front.serial + 1;
        std::swap(m_front, m_back);
    }
    m_published.notify_all();
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        on_publish = m_on_publish;
    }
    if (on_publish) on_publish();
}

}  // namespace pv
