// ui/panel_widgets.h: what the panel's section files (ui/panel*.cpp) share. Private to them.
#pragma once

#include <imgui.h>

#include <string>

namespace pv::ui {

inline const ImVec4 kWarningColour(1.f, 0.75f, 0.3f, 1.f);

// A status line: wrapped, in the warning colour when it reports a failure.
inline void status_text(const std::string& text, bool ok) {
    if (!ok) ImGui::PushStyleColor(ImGuiCol_Text, kWarningColour);
    ImGui::TextWrapped("%s", text.c_str());
    if (!ok) ImGui::PopStyleColor();
}

}  // namespace pv::ui
