// ui/refinement.cpp: the refinement schedule (see refinement.h).
#include "refinement.h"

#include <algorithm>

namespace pv::ui {

std::optional<RefinementSchedule::Restart> RefinementSchedule::update(const std::string& reason_in, double now,
                                                                      double since, uint64_t shown_generation,
                                                                      uint32_t shown_spp) {
    std::string reason = reason_in;
    const bool waiting = shown_generation < m_posted && now - m_last_change < kMaxDeferSeconds;
    if (reason == "camera" && m_level == m_coarse_level && waiting) {
        if (!m_deferred) m_deferred_since = since;
        m_deferred = true;
        return std::nullopt;
    }
    if (reason.empty() && m_deferred && !waiting) reason = "camera";
    if (!reason.empty()) {
        Restart r{reason, m_deferred ? std::min(m_deferred_since, since) : since};
        m_level = m_coarse_level;
        m_deferred = false;
        return r;
    }
    if (m_level > 1 && now - m_last_change >= kRestSeconds && shown_generation == m_posted && shown_spp >= 1) {
        m_level /= 2;
        return Restart{"refine", now};
    }
    return std::nullopt;
}

int RefinementSchedule::choose_coarse_level(double seconds_per_pixel, double full_pixels, double budget_seconds) {
    if (!(seconds_per_pixel > 0.0)) return kCoarsestLevel;
    for (int level = kMinCoarseLevel; level < kMaxCoarseLevel; level *= 2)
        if (seconds_per_pixel * full_pixels / double(level * level) <= budget_seconds) return level;
    return kMaxCoarseLevel;
}

void RefinementSchedule::measured_first_pass(double seconds, int pixels, double full_pixels, double budget_seconds) {
    if (pixels > 0 && seconds > 0.0)
        m_coarse_level = choose_coarse_level(seconds / double(pixels), full_pixels, budget_seconds);
}

RefinementSchedule::Restart RefinementSchedule::coarse(const std::string& reason, double now) {
    m_level = m_coarse_level;
    return Restart{reason, now};
}

void RefinementSchedule::posted(uint64_t generation, const Restart& restart, double now) {
    m_posted = generation;
    m_last_change = now;
    m_pending.push_back({generation, restart.since, restart.reason});  // latency from the input event
}

std::vector<RefinementSchedule::PendingFrame> RefinementSchedule::shown(uint64_t shown_generation) {
    std::vector<PendingFrame> done;
    while (!m_pending.empty() && m_pending.front().generation <= shown_generation) {
        done.push_back(m_pending.front());
        m_pending.pop_front();
    }
    return done;
}

void RefinementSchedule::reset() {
    m_pending.clear();
    m_posted = 0;
    m_deferred = false;
    m_coarse_level = kCoarsestLevel;  // a new scene: its pass times are not known yet
}

double RefinementSchedule::wait_timeout(double now, double idle_timeout) const {
    return m_deferred ? std::max(0.0, m_last_change + kMaxDeferSeconds - now) : idle_timeout;
}

}  // namespace pv::ui
