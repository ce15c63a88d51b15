// ui/frame_stats.cpp: frame timing and the stats log line (see frame_stats.h).
#include "frame_stats.h"

#include <algorithm>
#include <ctime>

namespace pv::ui {
namespace {
double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
}  // namespace

void FrameStats::begin_frame() { m_cpu_start = thread_cpu_seconds(); }

void FrameStats::end_frame(double wall_ms) {
    m_cpu_ms_sum += (thread_cpu_seconds() - m_cpu_start) * 1e3;
    m_last_ms = wall_ms;
    m_ms_sum += wall_ms;
    m_ms_max = std::max(m_ms_max, wall_ms);
    ++m_frames;
    ++m_total;
}

void FrameStats::log_if_due(ViewLog& log, const Snapshot& s) {
    const double now = log.now();
    if (m_since < 0.0) m_since = now;
    if (now - m_since < 1.0) return;
    log.line(
        "stats gen=%llu size=%dx%d spp=%u render_s=%.2f spp_per_s=%.2f mrays_per_s=%.2f ms_per_pass=%.1f "
        "rel_mse=%.3e frames=%d frame_ms_avg=%.2f frame_ms_max=%.2f frame_cpu_ms_avg=%.2f passes_shown=%d "
        "passes_denoised=%d denoised_spp=%u",
        (unsigned long long)s.generation, s.width, s.height, s.spp, s.seconds,
        s.seconds > 0.0 ? s.spp / s.seconds : 0.0, s.mrays_per_s, s.ms_per_pass, s.rel_mse, m_frames,
        m_frames ? m_ms_sum / m_frames : 0.0, m_ms_max, m_frames ? m_cpu_ms_sum / m_frames : 0.0, m_passes,
        m_passes_denoised, s.denoised_spp);
    m_since = now;
    m_frames = m_passes = m_passes_denoised = 0;
    m_ms_sum = m_ms_max = m_cpu_ms_sum = 0.0;
}

void log_frames_shown(ViewLog& log, RefinementSchedule& schedule, const Snapshot& shown, double end) {
    for (const RefinementSchedule::PendingFrame& p : schedule.shown(shown.generation))
        log.line(
            "frame gen=%llu shown_gen=%llu latency_ms=%.1f reason=%s size=%dx%d spp=%u ready_ms=%.1f "
            "features_ms=%.1f denoise_ms=%.1f pass_ms=%.1f wait_ms=%.1f",
            (unsigned long long)p.generation, (unsigned long long)shown.generation, (end - p.since) * 1e3,
            p.reason.c_str(), shown.width, shown.height, shown.spp, shown.first_ready_ms, shown.features_ms,
            shown.denoise_ms, shown.ms_per_pass, shown.wait_ms);
}

}  // namespace pv::ui
