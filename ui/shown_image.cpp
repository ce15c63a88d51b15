// ui/shown_image.cpp: the accumulation on screen (see shown_image.h).
#include "shown_image.h"

#include <utility>

namespace pv::ui {

bool ShownImage::update(const std::function<bool(Snapshot&)>& latest) {
    if (!latest(m_incoming) || m_incoming.generation < m_shown.generation) return false;
    std::swap(m_shown, m_incoming);
    m_incoming.serial = m_shown.serial;  // latest() copies only what is newer than this
    if (m_shown.generation != m_history_generation) {
        m_history.clear();
        m_history_generation = m_shown.generation;
    }
    // Samples taken per pixel on average: the passes without adaptive sampling.
    const double pixels = double(m_shown.width) * double(m_shown.height);
    const double spp = pixels > 0.0 && m_shown.paths > 0 ? double(m_shown.paths) / pixels : double(m_shown.spp);
    m_history.add(spp, m_shown.seconds, m_shown.rel_mse);
    return true;
}

void ShownImage::reset() {
    m_shown = Snapshot{};
    m_incoming = Snapshot{};
    m_history.clear();
    m_history_generation = 0;
}

}  // namespace pv::ui
