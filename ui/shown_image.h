// ui/shown_image.h: the accumulation on screen. It takes the renderer's newest published pass unless it belongs to
// an older request than the one shown (a pass finishing after a restart), and keeps the convergence history of
// the shown generation (cleared when a new one appears). Window-free: the renderer's latest() is passed in.
#pragma once

#include <functional>
#include <vector>

#include "convergence.h"
#include "core/frame/progressive.h"

namespace pv::ui {

class ShownImage {
public:
    // `latest` copies a newer snapshot into its argument and returns whether it did (ProgressiveRenderer::latest).
    // True when the shown snapshot changed.
    bool update(const std::function<bool(Snapshot&)>& latest);
    // A new renderer: its generations restart at 1, so everything about the old one is forgotten.
    void reset();

    const Snapshot& shown() const { return m_shown; }
    // What the display shows: shown(), except that with a render region the pixels outside it hold the last image
    // shown before the region was set (scaled to this size, nearest pixel), times kDimming; inside, the region's
    // accumulation. Snapshots save shown(), black outside.
    const Snapshot& displayed() const { return m_region_active ? m_displayed : m_shown; }
    static constexpr float kDimming = 0.4f;
    const ConvergenceHistory& history() const { return m_history; }

private:
    void composite();

    Snapshot m_shown, m_incoming;  // m_incoming: the buffer latest() fills, swapped in when taken
    Snapshot m_displayed;          // displayed() with a region
    bool m_region_active = false;
    std::vector<float> m_backdrop;  // the last image without a region (rgb, or denoised when shown so)
    int m_backdrop_w = 0, m_backdrop_h = 0;
    ConvergenceHistory m_history;
    uint64_t m_history_generation = 0;
};

}  // namespace pv::ui
