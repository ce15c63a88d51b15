// ui/dark_view.h: whether the image on screen reads as dark while no sky or sun lights the scene (its own lights
// barely reach the view: Blender's exporter writes lamps but not the world), so that the panel can offer fill light
// in one click (issue 41 item 6). The measure and its bound are core's (core/image/metrics.h:
// mean_display_luminance, kDarkMeanLuminance), as in pathview render's hint. Window-free.
#pragma once

#include <cstdint>

#include "core/frame/snapshot.h"

namespace pv::ui {

class DarkView {
public:
    // The shown snapshot (measured again only when a new one is published) and whether the environment emits.
    // True while the view is dark and nothing but the scene's own lights lights it.
    bool update(const Snapshot& shown, bool environment_lit);
    double mean() const { return m_mean; }

private:
    uint64_t m_generation = 0, m_serial = 0;
    double m_mean = 1.0;
};

}  // namespace pv::ui
