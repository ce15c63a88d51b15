// ui/panel_compare.cpp: the panel's Compare section (hold B, views, divider, an EXR as B) and the labels it draws
// on the image.
#include <imgui.h>

#include <cmath>
#include <cstdio>

#include "panel.h"
#include "panel_widgets.h"

namespace pv::ui {

void Panel::compare(const PanelFacts& facts, PanelActions& act) {
    static const Compare kNone;
    const Compare& c = facts.compare ? *facts.compare : kNone;
    if (ImGui::Button("Hold B (B)")) act.compare.hold = true;
    log_widget("hold_b");
    if (c.has_b()) {
        ImGui::SameLine();
        if (ImGui::Button("Clear B")) act.compare.clear = true;
        int view = static_cast<int>(c.view());
        ImGui::SetNextItemWidth(200.f);
        if (ImGui::Combo("view (C, V)", &view, "A\0A | B split\0B\0|A-B|/(B+0.01)\0"))
            act.compare.view = CompareView(view);
        log_widget("compare_view");
        if (c.view() == CompareView::Split) {
            float d = c.divider();
            ImGui::SetNextItemWidth(200.f);
            if (ImGui::SliderFloat("divider (right drag)", &d, 0.f, 1.f, "%.2f")) act.compare.divider = d;
        }
    } else {
        ImGui::SameLine();
        ImGui::TextDisabled("no B held");
    }
    if (!c.status().empty()) status_text(c.status(), c.ok());
    if (facts.compare_camera_moved) status_text("camera moved since B was held", false);
    ImGui::SetNextItemWidth(-FLT_MIN);
    const bool entered = ImGui::InputTextWithHint("##compare_path", "reference.exr", m_compare_path,
                                                  sizeof m_compare_path, ImGuiInputTextFlags_EnterReturnsTrue);
    log_widget("compare_path");
    if ((ImGui::Button("Load EXR as B") || entered) && m_compare_path[0]) act.compare.load = m_compare_path;
    log_widget("compare_load");
}

void draw_compare_overlay(const Compare& c, bool camera_moved, float w, float h) {
    if (c.view() == CompareView::Off || w <= 0.f || h <= 0.f) return;
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    const ImU32 text = IM_COL32(255, 255, 255, 255), shade = IM_COL32(0, 0, 0, 160);
    auto label = [&](ImVec2 at, const char* s) {
        const ImVec2 size = ImGui::CalcTextSize(s);
        dl->AddRectFilled(ImVec2(at.x - 3.f, at.y - 2.f), ImVec2(at.x + size.x + 3.f, at.y + size.y + 2.f), shade);
        dl->AddText(at, text, s);
    };
    // B: the file's name, or when it was held; short enough for a narrow image.
    std::string b = c.source();
    if (c.from_file()) b = b.substr(b.find_last_of('/') == std::string::npos ? 0 : b.find_last_of('/') + 1);
    b = "B: " + b + (camera_moved ? " (camera moved)" : "");
    switch (c.view()) {
        case CompareView::Split: {
            const float x = c.divider() * w;
            dl->AddLine(ImVec2(x, 0.f), ImVec2(x, h), IM_COL32(255, 255, 255, 200), 1.f);
            label(ImVec2(8.f, 8.f), "A: live");
            const float bw = ImGui::CalcTextSize(b.c_str()).x;
            label(ImVec2(std::max(x + 8.f, w - bw - 8.f), 8.f), b.c_str());
            break;
        }
        case CompareView::ShowB:
            label(ImVec2(8.f, 8.f), b.c_str());
            break;
        case CompareView::Difference:
            label(ImVec2(8.f, 8.f), "|A-B|/(B+0.01): 1e-3 blue .. 1 red");
            break;
        default:
            break;
    }
}

}  // namespace pv::ui
