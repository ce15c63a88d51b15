// ui/compare_display.h: the compare views (compare.h) on screen: keeps the display pass's B and difference textures
// and the view log in step with Compare as the panel's actions and new passes change it. Needs the GL context.
#pragma once

#include "compare.h"
#include "display.h"
#include "view_log.h"

namespace pv::ui {

class CompareDisplay {
public:
    CompareDisplay(Compare& compare, DisplayPass& display, ViewLog& log)
        : m_compare(compare), m_display(display), m_log(log) {}

    // B given on the command line (--compare).
    void set_b(Image image, const std::string& source);
    // A frame's actions (hold, load, clear, view): `displayed` is the image on screen, `shown` the accumulation it
    // comes from, `denoising` whether its denoised image is shown; `full_w` x `full_h` the image region's full
    // resolution.
    void apply(const CompareActions& act, const Snapshot& displayed, const Snapshot& shown, bool denoising,
               const CameraDesc& camera, int full_w, int full_h);
    // A new pass on screen: its error against B (logged, see log_error()), and the difference view's texture.
    void new_pass(const Snapshot& shown, const Snapshot& displayed, bool denoising);
    // The difference view's texture from `displayed` (after a new pass, or a denoise toggle).
    void upload_difference(const Snapshot& displayed, bool denoising);

private:
    // With a B (e.g. a converged reference, --compare), each newly shown pass logs its relMSE against B: of the image
    // on screen (the denoised one when shown) and of the raw mean. tests/gui/measure_viewer.sh's settle time reads it.
    void log_error(const Snapshot& shown, bool denoising);

    Compare& m_compare;
    DisplayPass& m_display;
    ViewLog& m_log;
};

}  // namespace pv::ui
