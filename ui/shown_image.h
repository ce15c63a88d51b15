// ui/shown_image.h: the accumulation on screen. It takes the renderer's newest published pass unless it belongs to
// an older request than the one shown (a pass finishing after a restart), and keeps the convergence history of
// the shown generation (cleared when a new one appears). Window-free: the renderer's latest() is passed in.
#pragma once

#include <functional>

#include "convergence.h"
#include "core/progressive.h"

namespace pv::ui {

class ShownImage {
public:
    // `latest` copies a newer snapshot into its argument and returns whether it did (ProgressiveRenderer::latest).
    // True when the shown snapshot changed.
    bool update(const std::function<bool(Snapshot&)>& latest);
    // A new renderer: its generations restart at 1, so everything about the old one is forgotten.
    void reset();

    const Snapshot& shown() const { return m_shown; }
    const ConvergenceHistory& history() const { return m_history; }

private:
    Snapshot m_shown, m_incoming;  // m_incoming: the buffer latest() fills, swapped in when taken
    ConvergenceHistory m_history;
    uint64_t m_history_generation = 0;
};

}  // namespace pv::ui
