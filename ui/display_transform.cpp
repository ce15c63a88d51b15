// ui/display_transform.cpp: see display_transform.h.
#include "display_transform.h"

#include <iterator>

#include "core/base/error.h"

namespace pv::ui {

bool choose_ocio_view(DisplayParams& display, OcioChoice& choice, const std::string& display_name,
                      const std::string& view) {
    if (!choice.config) {
        choice.status = "no OpenColorIO config: start with --ocio-config FILE or set $OCIO";
        return false;
    }
    try {
        display.ocio = std::make_shared<const OcioView>(choice.config, display_name, view, choice.input);
    } catch (const Error& e) {
        choice.status = e.what();
        return false;
    }
    display.transform = ViewTransform::Ocio;
    choice.status.clear();
    return true;
}

void cycle_view_transform(DisplayParams& display, OcioChoice& choice) {
    const int count = int(std::size(kViewTransformNames));
    int next = (int(display.transform) + 1) % count;
    if (ViewTransform(next) == ViewTransform::Ocio) {
        if (display.ocio && choice.config) {
            display.transform = ViewTransform::Ocio;
            return;
        }
        if (choose_ocio_view(display, choice, "", "")) return;
        next = 0;
    }
    display.transform = ViewTransform(next);
}

DisplayTransform display_transform(const DisplayParams& display) {
    DisplayTransform t;
    t.exposure = display.exposure;
    t.transform = display.transform == ViewTransform::Ocio && !display.ocio ? ViewTransform::Clamp : display.transform;
    t.ocio = display.ocio;
    return t;
}

}  // namespace pv::ui
