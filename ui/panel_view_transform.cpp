// ui/panel_view_transform.cpp: the Display section's view transform: a combo of the built-in curves and OpenColorIO
// (with a config), then the config's display and view. Display only: nothing here restarts the accumulation.
#include <imgui.h>

#include <iterator>

#include "display_transform.h"
#include "panel.h"
#include "panel_widgets.h"

namespace pv::ui {
namespace {

// The combo's labels, in the order of ViewTransform.
constexpr const char* kLabels[] = {"clamp",           "Reinhard (luminance)", "ACES filmic (Narkowicz fit)",
                                   "AgX (Blender 4)", "Khronos PBR Neutral",  "OpenColorIO"};
static_assert(std::size(kLabels) == std::size(kViewTransformNames));

}  // namespace

void Panel::view_transform(ViewState& state) {
    DisplayParams& d = state.display;
    OcioChoice& choice = state.ocio;
    int current = static_cast<int>(d.transform);
    const int count = int(std::size(kLabels)) - (choice.config ? 0 : 1);
    if (ImGui::Combo("view transform", &current, kLabels, count)) {
        if (ViewTransform(current) != ViewTransform::Ocio)
            d.transform = ViewTransform(current);
        else if (d.ocio)
            d.transform = ViewTransform::Ocio;
        else
            choose_ocio_view(d, choice, "", "");
        m_log.line("action view-transform %s", name_of(kViewTransformNames, d.transform));
    }
    log_widget("view_transform");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "T cycles them. PNG snapshots and `pathview render -o x.png --view-transform ...` use the "
            "same curves; EXR files stay linear.");
    if (!choice.config) {
        ImGui::TextDisabled("OpenColorIO: start with --ocio-config FILE or $OCIO");
    } else if (d.transform == ViewTransform::Ocio && d.ocio) {
        const std::string display = d.ocio->display(), view = d.ocio->view();
        if (ImGui::BeginCombo("display", display.c_str())) {
            for (const std::string& name : choice.config->displays())
                if (ImGui::Selectable(name.c_str(), name == display) && name != display)
                    choose_ocio_view(d, choice, name, "");
            ImGui::EndCombo();
        }
        if (ImGui::BeginCombo("view", view.c_str())) {
            for (const std::string& name : choice.config->views(display))
                if (ImGui::Selectable(name.c_str(), name == view) && name != view)
                    choose_ocio_view(d, choice, display, name);
            ImGui::EndCombo();
        }
        ImGui::TextDisabled("%s (a %d^3 LUT on screen)", choice.config->path().c_str(), kDisplayLutSize);
    }
    if (!choice.status.empty()) status_text(choice.status, false);
}

}  // namespace pv::ui
