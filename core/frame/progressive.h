// core/frame/progressive.h: the asynchronous driver of a Renderer, for the viewer. A driver thread renders passes back
// to back; restart() only posts a request and never waits, and after each completed pass the driver publishes a
// Snapshot (core/frame/snapshot.h) under a mutex held only for the copy.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/denoise/aov.h"
#include "core/denoise/denoise_atrous.h"
#include "core/frame/renderer.h"
#include "core/frame/snapshot.h"

namespace pv {

// The pass in flight is cancelled and the film restarted before the next pass, so no sample of an older request
// ever lands in a newer accumulation. Every snapshot carries the generation of the request it belongs to (restart()
// returns it).
class ProgressiveRenderer {
public:
    // Builds the Renderer (BVH; throws pv::Error) and starts the driver thread, idle until the first restart().
    ProgressiveRenderer(std::shared_ptr<const Scene> scene, int threads = 0);
    // Cancels the pass in flight and joins the driver thread.
    ~ProgressiveRenderer();
    ProgressiveRenderer(const ProgressiveRenderer&) = delete;
    ProgressiveRenderer& operator=(const ProgressiveRenderer&) = delete;

    // Posts a new request and returns its generation. Never blocks on a pass. Throws pv::Error (and posts
    // nothing) for an invalid camera or size, or materials of the wrong count.
    uint64_t restart(const RenderRequest& request);
    // Pausing stops after the pass in flight (which is still published); resuming continues the accumulation.
    void set_paused(bool paused);
    // Denoised snapshots (Snapshot::denoised) on or off; never restarts or touches the accumulation. While
    // rendering, each pass is a-trous filtered (throttled to a third of the time). Once rendering stops (paused or
    // at its target), the driver publishes the a-trous image of the film as it is, then NFOR's (final quality,
    // seconds to a minute at 640x480) when the film has kNforMinSpp samples; a restart, resuming, a new target or
    // turning denoising off cancels NFOR in flight.
    void set_denoise(bool on);
    static constexpr uint32_t kNforMinSpp = 4;  // two per half buffer, NFOR's least
    // Stops rendering (target_reached) once spp >= target_spp or seconds >= target_seconds, or once every pixel has
    // reached the request's noise threshold; 0 = no target.
    void set_target(uint32_t target_spp, double target_seconds);
    // Light groups (docs/light-groups.md): the driver keeps them (Renderer::set_light_groups) and publishes the
    // film as mixed with these gains (the snapshot's image, error estimate and denoised image); never restarts or
    // touches the accumulation: the mix is re-published after the pass in flight, at once while stopped. Cancels
    // NFOR in flight (its image was of the old mix).
    void set_light_gains(LightGains gains);

    // Copies the latest snapshot into `out` if its serial is newer than out.serial; returns whether it did.
    bool latest(Snapshot& out) const;
    // The generation of the latest snapshot (0 before the first); cheap, for the viewer's frame pacing.
    uint64_t published_generation() const;
    // Blocks until a snapshot of `generation` with spp >= min_spp is published, or the timeout passes
    // (tests and tools; the viewer, at most the rest of a display refresh after posting a restart).
    bool wait_for(uint64_t generation, uint32_t min_spp, std::chrono::milliseconds timeout) const;
    // Asks for the accumulation as a resumable partial render (core/partial/partial.h; samples [0, spp)), made by the
    // driver between passes, also while paused or stopped (after the first pass of a new accumulation). Once it is
    // made, take_partial() returns it (once) and the on_publish callback runs.
    void request_partial();
    std::optional<PartialRender> take_partial();
    // Why the last requested partial render was refused (once; "" if it was not): adaptive sampling's films are
    // not sums over sample indices, so they cannot be resumed or merged (core/frame/adaptive.h).
    std::string take_partial_refusal();
    // Called on the driver thread after each publication (the viewer wakes its event loop with it).
    // Set before the first restart().
    void set_on_publish(std::function<void()> callback);

    // Traces the primary ray through film pixel `film_px` of an image of width x height seen by `camera`.
    // Thread-safe (the BVH is read-only); nothing when the ray escapes.
    std::optional<PickResult> pick(const CameraDesc& camera, int width, int height, vec2 film_px) const;
    const Scene& scene() const { return *m_scene; }
    int threads() const;

private:
    void drive();
    // Under m_mutex, on the driver thread.
    bool target_reached() const;
    bool should_render() const;
    bool partial_due() const;  // a requested partial render can be made now
    bool denoise_due() const;  // denoising is on and the film's last state has not been denoised
    bool nfor_due() const;     // rendering stopped, the a-trous image is out, and NFOR has not seen this film
    void publish(uint64_t generation, bool target_reached, bool force_denoise = false);
    // On the driver thread: refreshes m_denoised_image for the current film when due (or forced).
    void update_denoised(uint64_t generation, bool force);
    // On the driver thread, once stopped: NFOR of the film (features, then the filter), published unless cancelled.
    void run_nfor(uint64_t generation);
    double seconds_to_threshold(float threshold) const;
    // The film as shown: the renderer's, or m_mixed holding its mix with the light gains (driver thread).
    const Film& shown_film();
    Film m_mixed;

    std::shared_ptr<const Scene> m_scene;
    Renderer m_renderer;  // used by the driver thread only, apart from its read-only BVH and scene
    std::atomic<bool> m_cancel{false};
    std::atomic<bool> m_nfor_cancel{false};  // raised (under m_mutex) by whatever ends the stop NFOR runs in

    // Requests and control, under m_mutex.
    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    std::optional<RenderRequest> m_pending;
    uint64_t m_generation = 0;  // of the last request posted
    bool m_paused = false;
    bool m_quit = false;
    bool m_partial_requested = false;
    bool m_denoise = false;
    std::optional<LightGains> m_gains_pending;  // set_light_gains, until the driver takes it
    uint32_t m_target_spp = 0;
    double m_target_seconds = 0.0;
    std::function<void()> m_on_publish;
    // (spp, worst active relative MSE) at the adaptive checkpoints of the current accumulation; driver thread.
    std::vector<std::pair<double, double>> m_error_history;
    // Denoising state, driver thread only: which accumulation (and size) the filter's features are of, the last
    // denoised image, what it was made from, and the filter's timing (for the throttle).
    uint64_t m_features_generation = 0;
    int m_features_width = 0, m_features_height = 0;
    int m_features_samples = 0;  // per pixel, of the features the filter holds
    AtrousDenoiser m_atrous;     // keeps its feature planes and memory between frames
    Image m_denoised_image;
    uint64_t m_denoised_generation = 0;
    uint32_t m_denoised_spp = 0;
    bool m_denoised_nfor = false;
    uint64_t m_nfor_generation = 0;  // the film NFOR last finished (or gave up) on
    uint32_t m_nfor_spp = 0;
    double m_nfor_seconds = 0.0;  // features and filter (apart from the a-trous throttle's m_denoise_seconds)
    double m_denoise_seconds = 0.0;
    std::chrono::steady_clock::time_point m_denoise_end{};
    double m_features_seconds = 0.0;                           // the last feature pass
    std::chrono::steady_clock::time_point m_request_taken{};   // when the driver took the current request
    std::chrono::steady_clock::time_point m_request_posted{};  // when restart() posted it (under m_mutex)
    double m_wait_ms = 0.0;
    uint64_t m_first_generation = 0;  // the accumulation whose first publication the next two describe
    double m_first_ready_ms = 0.0, m_first_features_ms = 0.0;

    // The published snapshot, under m_snapshot_mutex; the driver fills m_back outside it.
    mutable std::mutex m_snapshot_mutex;
    mutable std::condition_variable m_published;
    Snapshot m_front;
    Snapshot m_back;
    std::optional<PartialRender> m_partial;  // made on request_partial(), until taken
    std::string m_partial_refusal;           // or why it was not made, until taken

    std::thread m_thread;  // last: started after everything above exists
};

}  // namespace pv
