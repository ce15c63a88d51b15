// ui/dark_view.cpp: see dark_view.h.
#include "dark_view.h"

#include "core/image/metrics.h"

namespace pv::ui {

bool DarkView::update(const Snapshot& shown, bool environment_lit) {
    if (shown.spp == 0 || shown.rgb.empty()) return false;  // nothing rendered yet: no verdict
    if (shown.generation != m_generation || shown.serial != m_serial) {
        m_generation = shown.generation;
        m_serial = shown.serial;
        m_mean = mean_display_luminance(shown.rgb.data(), shown.rgb.size() / 3);
    }
    return !environment_lit && m_mean < kDarkMeanLuminance;
}

}  // namespace pv::ui
