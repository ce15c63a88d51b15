// ui/frame_stats.h: the viewer's telemetry: UI frame times (wall and the UI thread's CPU time) gathered per frame,
// and the once-a-second "stats" line of the --log-file with the accumulation on screen (the GUI test and
// tests/gui/measure_viewer.sh read it), and the "frame" lines with each request's input-to-frame latency. Window-free.
#pragma once

#include "core/frame/progressive.h"
#include "refinement.h"
#include "view_log.h"

namespace pv::ui {

class FrameStats {
public:
    void begin_frame();
    void end_frame(double wall_ms);
    double last_ms() const { return m_last_ms; }
    int total_frames() const { return m_total; }
    // Writes the stats line when a second has passed since the last one, then starts a new second.
    void log_if_due(ViewLog& log, const Snapshot& shown);
    // A pass went on screen, denoised at its own spp or not (the stats line's passes_shown, passes_denoised).
    void pass_shown(bool denoised) {
        ++m_passes;
        m_passes_denoised += int(denoised);
    }

private:
    double m_since = -1.0;  // log time of the last stats line
    double m_cpu_start = 0.0;
    int m_frames = 0, m_total = 0;
    int m_passes = 0, m_passes_denoised = 0;
    double m_ms_sum = 0.0, m_ms_max = 0.0, m_last_ms = 0.0;
    double m_cpu_ms_sum = 0.0;  // CPU time of the UI thread (Mesa's llvmpipe threads not included)
};

// Logs a "frame" line (generation, latency since its input event, reason, size, spp) for every request the
// snapshot on screen completes (RefinementSchedule::shown), `end` being the time the frame was on screen.
void log_frames_shown(ViewLog& log, RefinementSchedule& schedule, const Snapshot& shown, double end);

}  // namespace pv::ui
