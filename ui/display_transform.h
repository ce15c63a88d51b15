// ui/display_transform.h: the viewer's choice of view transform (Display section, T key): the built-in curves and,
// when a config was given (--ocio-config or $OCIO), an OpenColorIO display/view, built on the UI thread when
// chosen (a failure keeps the view on screen and says why). Window-free.
#pragma once

#include <memory>
#include <string>

#include "core/image/ocio_view.h"
#include "core/image/view_transform.h"
#include "display.h"

namespace pv::ui {

struct OcioChoice {
    std::shared_ptr<const OcioConfig> config;  // null: OpenColorIO is not offered
    std::string input = "scene_linear";        // the colour space pathview's linear Rec.709 RGB is handed over as
    std::string status;                        // the last failure; empty when the choice worked
};

// Builds `view` of `display_name` (empty: the config's defaults) into display.ocio and selects OpenColorIO; on
// failure (choice.status says why) `display` is unchanged and false is returned.
bool choose_ocio_view(DisplayParams& display, OcioChoice& choice, const std::string& display_name,
                      const std::string& view);
// The next transform in the order of kViewTransformNames; OpenColorIO only with a config (its last view, or the
// config's default).
void cycle_view_transform(DisplayParams& display, OcioChoice& choice);
// What a PNG of the image on screen goes through (the colour view's exposure and transform).
DisplayTransform display_transform(const DisplayParams& display);

}  // namespace pv::ui
