// ui/panel.cpp: the panel's frame and its sections, top to bottom: warnings, progress, convergence, estimator,
// display (ui/panel_render.cpp), snapshot, compare (ui/panel_compare.cpp), light, camera (with bookmarks), materials,
// scene (ui/panel_scene.cpp).
#include "panel.h"

#include <imgui.h>

#include <cstdio>

#include "panel_widgets.h"

namespace pv::ui {

PanelActions Panel::draw(ViewState& state, CameraController& camera_ctl, const PanelFacts& facts, float width) {
    PanelActions act;
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - width, 0.f));
    ImGui::SetNextWindowSize(ImVec2(width, io.DisplaySize.y));
    ImGui::Begin("pathview", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::TextWrapped("%s: %zu triangles", facts.scene_name.c_str(), facts.triangles);
    for (const std::string& w : facts.warnings) ImGui::TextColored(kWarningColour, "warning: %s", w.c_str());
    if (!state.drop_status.empty()) status_text(state.drop_status, state.drop_ok);
    if (state.settings.max_depth < RenderSettings{}.max_depth)
        ImGui::TextColored(kWarningColour, "max depth %d truncates paths (biased)", state.settings.max_depth);
    if (facts.dark_view) dark_view_hint(state, facts, act);

    if (ImGui::CollapsingHeader("Progress", ImGuiTreeNodeFlags_DefaultOpen)) progress(state, facts, act);
    if (ImGui::CollapsingHeader("Convergence", ImGuiTreeNodeFlags_DefaultOpen)) convergence(facts);
    if (ImGui::CollapsingHeader("Estimator", ImGuiTreeNodeFlags_DefaultOpen)) estimator(state, facts, act);
    if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) display(state, facts);
    if (ImGui::CollapsingHeader("Snapshot", ImGuiTreeNodeFlags_DefaultOpen)) snapshots(state, act);
    const bool compare_open = ImGui::CollapsingHeader("Compare", ImGuiTreeNodeFlags_DefaultOpen);
    log_widget("compare_header");
    if (compare_open) compare(facts, act);
    const bool light_open = ImGui::CollapsingHeader("Light");
    log_widget("light_header");
    if (light_open) lighting(state, act);
    const bool camera_open = ImGui::CollapsingHeader("Camera");
    log_widget("camera_header");
    if (camera_open) {
        camera(state, camera_ctl, act);
        bookmarks(state, act);
    }
    const bool materials_open = ImGui::CollapsingHeader("Materials");
    log_widget("materials_header");
    if (materials_open) materials(state, act);
    const bool scene_open = ImGui::CollapsingHeader("Scene");
    log_widget("scene_header");
    if (scene_open) scene(state, act);
    ImGui::End();
    return act;
}

std::string shown_image(const ViewState& state, const Snapshot* s) {
    if (state.display.view != View::Colour) return "false colour (raw)";
    if (!state.display.denoise) return "RAW";
    if (!s || s->denoised.empty()) return "RAW (denoising...)";
    char buf[64];
    std::snprintf(buf, sizeof buf, "DENOISED%s at %u/%u spp", s->denoised_nfor ? " (NFOR)" : "", s->denoised_spp,
                  s->spp);
    return buf;
}

// The scene's own lights leave the view dark (no sky or sun): say so, and offer fill light in one click. Either
// restarts the accumulation, as any light edit does; nothing changes until a button is pressed.
void Panel::dark_view_hint(ViewState& state, const PanelFacts& facts, PanelActions& act) {
    ImGui::PushStyleColor(ImGuiCol_Text, kWarningColour);
    ImGui::TextWrapped("The view is dark (mean %.2g): the scene's own lights barely reach it. Add fill light:",
                       facts.dark_mean);
    ImGui::PopStyleColor();
    if (ImGui::Button("default sky")) {
        act.fill_default_sky = true;
        m_log.line("fill default sky");
    }
    log_widget("fill_default_sky");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("As --environment sky: the scene is rebuilt with the default sky.");
    ImGui::SameLine();
    if (ImGui::Button("grey studio fill")) {
        state.environment.background = vec3(0.5f);
        state.environment.strength = 1.f;
        act.environment_changed = true;
        m_log.line("fill grey");
    }
    log_widget("fill_grey");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("As --environment 0.5: a uniform grey sky of radiance 0.5 (the Light section edits it).");
}

void Panel::log_widget(const char* name) {
    if (!ImGui::IsItemVisible()) return;
    const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
    // A checkbox's box is at its left end: aim at the box, which is square with the item's height.
    const std::pair<int, int> at(int(lo.x + std::min(hi.x - lo.x, hi.y - lo.y) * 0.5f), int(0.5f * (lo.y + hi.y)));
    auto it = m_logged.find(name);
    if (it != m_logged.end() && it->second == at) return;
    m_logged[name] = at;
    m_log.line("widget name=%s x=%d y=%d", name, at.first, at.second);
}

}  // namespace pv::ui
