// ui/refinement.h: the viewer's refinement schedule: after any change the accumulation restarts at a coarse
// resolution, so the picture follows the mouse, and is refined at rest. It also keeps the requests waiting for their
// first frame on screen, for the input-to-frame latency in the log. Window-free; the viewer feeds it times (seconds)
// and the generation of the snapshot on screen.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace pv::ui {

// Any change restarts the accumulation at a coarse resolution (1/16, 1/8, 1/4 or 1/2 of the image region's, the finest
// whose first frame the last measured pass time predicts within about one display refresh; 1/4 before any
// measurement), so the picture follows the mouse; at rest (no change for kRestSeconds, and the pass on screen belongs
// to the latest request) it is refined to 1/2, then full resolution. While the camera moves, a new coarse request is
// deferred until the coarse pass in flight has landed (at most kMaxDeferSeconds), so a pass that takes longer than a
// UI frame is never cancelled for the next mouse position and the picture keeps moving.
class RefinementSchedule {
public:
    static constexpr int kCoarsestLevel = 4;         // resolution divisor right after a change, until measured
    static constexpr int kMaxCoarseLevel = 16;       // the coarse levels chosen from measured pass times:
    static constexpr int kMinCoarseLevel = 2;        //   16, 8, 4 or 2
    static constexpr double kRestSeconds = 0.12;     // no change for this long: refine one level
    static constexpr double kMaxDeferSeconds = 1.0;  // a camera move waits at most this long for the coarse pass

    // A restart the viewer should post now, at resolution divisor level().
    struct Restart {
        std::string reason;  // "camera,material", "refine", ...
        double since = 0.0;  // the input event it answers (for the latency figure)
    };
    // A request waiting for its first frame on screen.
    struct PendingFrame {
        uint64_t generation = 0;
        double since = 0.0;
        std::string reason;
    };

    // This frame: `reason` lists the changes ("" for none; "camera" alone is a camera move that may be deferred),
    // `since` the first input event behind them; shown_generation / shown_spp describe the snapshot on screen.
    std::optional<Restart> update(const std::string& reason, double now, double since, uint64_t shown_generation,
                                  uint32_t shown_spp);
    // A restart the viewer posts outside update() (first frame, new scene): at the coarsest level.
    Restart coarse(const std::string& reason, double now);
    // The viewer posted a restart of `generation` (renderer->restart() succeeded).
    void posted(uint64_t generation, const Restart& restart, double now);
    // The requests the snapshot of `shown_generation` completes, oldest first (removed from the schedule).
    std::vector<PendingFrame> shown(uint64_t shown_generation);
    // The first pass's resolution divisor: the finest of 2, 4, 8, 16 whose predicted first frame,
    // seconds_per_pixel * full_pixels / level^2, fits budget_seconds; 16 when none does, kCoarsestLevel when nothing
    // was measured yet (seconds_per_pixel <= 0). Pure.
    static int choose_coarse_level(double seconds_per_pixel, double full_pixels, double budget_seconds);
    // The driver took `seconds` from a request to the first snapshot of `pixels` pixels: restarts from now on start
    // at choose_coarse_level() for an image region of full_pixels and a budget of budget_seconds.
    void measured_first_pass(double seconds, int pixels, double full_pixels, double budget_seconds);
    int coarse_level() const { return m_coarse_level; }
    // A new renderer: generations restart at 1, nothing is pending.
    void reset();

    int level() const { return m_level; }
    uint64_t posted_generation() const { return m_posted; }
    bool deferred() const { return m_deferred; }
    // How long the event loop may sleep before update() must run again (a deferred move's wait expiring).
    double wait_timeout(double now, double idle_timeout) const;
    bool deferral_expired(double now) const { return m_deferred && now >= m_last_change + kMaxDeferSeconds; }

private:
    int m_level = kCoarsestLevel;
    int m_coarse_level = kCoarsestLevel;  // where a change restarts
    uint64_t m_posted = 0;
    double m_last_change = 0.0;
    bool m_deferred = false;        // a camera move waits for the coarse pass in flight
    double m_deferred_since = 0.0;  // its first input event
    std::deque<PendingFrame> m_pending;
};

}  // namespace pv::ui
