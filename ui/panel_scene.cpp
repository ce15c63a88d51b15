// ui/panel_scene.cpp: the panel's scene sections: snapshot, light, camera (with bookmarks), materials, scene.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/scene/material_params.h"
#include "panel.h"
#include "panel_widgets.h"

namespace pv::ui {
namespace {

// Edits one material; true if it changed.
bool edit_material(Material& m) {
    BsdfParams f = bsdf_params(m.bsdf);
    int type = int(f.type);
    bool changed = ImGui::Combo("type", &type, "diffuse\0glossy\0mirror\0glass\0metallic-roughness\0");
    f = with_type(f, BsdfType(type));  // a new type's fields by meaning (core/scene/material_params.h)
    if (f.type != BsdfType::Glass)
        changed |= ImGui::ColorEdit3(f.type == BsdfType::Mirror ? "reflectance" : "base colour", &f.base.x,
                                     ImGuiColorEditFlags_Float);
    if (m.base_color_texture != kNoIndex && f.type != BsdfType::Glass && f.type != BsdfType::Mirror)
        ImGui::TextDisabled("a base colour texture replaces this colour");
    if (f.type == BsdfType::Glossy) {
        changed |= ImGui::ColorEdit3("specular", &f.specular.x, ImGuiColorEditFlags_Float);
        changed |= ImGui::SliderFloat("roughness", &f.roughness, kMinAlpha, 1.f, "%.3f", ImGuiSliderFlags_Logarithmic);
    }
    if (f.type == BsdfType::Glass)
        changed |= ImGui::SliderFloat("IOR", &f.ior, 1.0001f, 3.f, "%.3f", ImGuiSliderFlags_AlwaysClamp);
    if (f.type == BsdfType::MetallicRoughness) {  // glTF's factors (core/scene/bsdf_pbr.h)
        changed |= ImGui::SliderFloat("metallic", &f.metallic, 0.f, 1.f, "%.3f", ImGuiSliderFlags_AlwaysClamp);
        changed |= ImGui::SliderFloat("roughness", &f.roughness, 0.f, 1.f, "%.3f", ImGuiSliderFlags_AlwaysClamp);
        changed |= ImGui::SliderFloat("IOR", &f.ior, 1.f, 3.f, "%.3f", ImGuiSliderFlags_AlwaysClamp);
        changed |= ImGui::SliderFloat("transmission", &f.transmission, 0.f, 1.f, "%.3f", ImGuiSliderFlags_AlwaysClamp);
        changed |= ImGui::SliderFloat("specular", &f.specular_weight, 0.f, 1.f, "%.3f", ImGuiSliderFlags_AlwaysClamp);
        // KHR_materials_clearcoat and _sheen: layers over the base, present only when non-zero
        changed |= ImGui::SliderFloat("clearcoat", &f.clearcoat, 0.f, 1.f, "%.3f", ImGuiSliderFlags_AlwaysClamp);
        if (f.clearcoat > 0.f)
            changed |= ImGui::SliderFloat("clearcoat roughness", &f.clearcoat_roughness, 0.f, 1.f, "%.3f",
                                          ImGuiSliderFlags_AlwaysClamp);
        changed |= ImGui::ColorEdit3("sheen colour", &f.sheen_color.x, ImGuiColorEditFlags_Float);
        if (max_component(f.sheen_color) > 0.f)
            changed |= ImGui::SliderFloat("sheen roughness", &f.sheen_roughness, 0.f, 1.f, "%.3f",
                                          ImGuiSliderFlags_AlwaysClamp);
        if (m.has_layer_textures()) ImGui::TextDisabled("clearcoat / sheen textures scale these factors");
    }
    if (changed) set_bsdf(m, f);  // fitted to the material's textures, as the loader fits it

    // Emission as a colour (largest channel 1) times a strength.
    float strength = max_component(m.emission);
    vec3 colour = strength > 0.f ? m.emission / strength : vec3(1.f);
    bool emission_changed = ImGui::ColorEdit3("emission colour", &colour.x, ImGuiColorEditFlags_Float);
    // About 1% of the value per pixel dragged, so dim and bright emitters both edit comfortably.
    emission_changed |=
        ImGui::DragFloat("emission strength", &strength, std::max(0.01f, 0.01f * strength), 0.f, 1e4f, "%.3f");
    if (emission_changed) {
        const float c = max_component(colour);
        m.emission = c > 0.f ? colour / c * std::max(strength, 0.f) : vec3(0.f);
    }
    return changed || emission_changed;
}

}  // namespace

void Panel::snapshots(ViewState& state, PanelActions& act) {
    // The render region: snapshots record it (pathview:region); a resumable EXR covers the whole image only.
    if (state.region) {
        ImGui::Text("Region %s", format_region(*state.region).c_str());
        if (state.adaptive.enabled() || state.adaptive.allocate)
            status_text("not applied: adaptive sampling is on", false);
        ImGui::SameLine();
        if (ImGui::Button("Clear region (X)")) {
            state.region.reset();
            act.region_changed = true;
        }
        log_widget("clear_region");
    } else {
        ImGui::TextDisabled("Region: whole image (Ctrl+left drag sets one)");
    }
    if (ImGui::Button("Save EXR (Ctrl+S)")) act.save = true;
    log_widget("save");
    ImGui::SameLine();
    if (ImGui::Button("Save PNG (Ctrl+Shift+S)")) act.save_png = true;
    log_widget("save_png");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "The image on screen through the exposure and view transform: the bytes `pathview render "
            "-o x.png` writes for the same film and flags");
    ImGui::TextDisabled("to %s", state.snapshot_dir.c_str());
    if (ImGui::Button("Save resumable EXR")) act.save_resumable = true;
    log_widget("save_resumable");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "The accumulation's exact per-pixel sums (a partial render):\n"
            "pathview render --resume FILE --spp N -o OUT.exr adds N samples.");
    if (!state.snapshot_status.empty()) status_text(state.snapshot_status, state.snapshot_ok);
}

void Panel::lighting(ViewState& state, const PanelFacts& facts, PanelActions& act) {
    light_mix(state, facts, act);
    EnvironmentSettings& e = state.environment;
    if (state.has_environment_map) {
        act.environment_changed |= ImGui::SliderFloat("map rotation", &e.rotation_deg, -180.f, 180.f, "%.0f deg");
    } else {
        act.environment_changed |=
            ImGui::ColorEdit3("sky colour", &e.background.x, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR);
    }
    act.environment_changed |=
        ImGui::DragFloat("sky strength", &e.strength, 0.01f * std::max(e.strength, 0.1f), 0.f, 1e6f, "%.3g");
    // The sun: elevation and azimuth about +y, its irradiance and angular radius.
    bool sun_on = !is_black(e.sun_irradiance);
    if (ImGui::Checkbox("sun", &sun_on)) {
        e.sun_irradiance = vec3(sun_on ? 5.f : 0.f);
        act.environment_changed = true;
    }
    if (sun_on) {
        const vec3 d = glm::normalize(e.sun_direction);
        float elevation = glm::degrees(std::asin(glm::clamp(d.y, -1.f, 1.f)));
        float azimuth = glm::degrees(std::atan2(d.z, d.x));
        bool moved = ImGui::SliderFloat("sun elevation", &elevation, -10.f, 90.f, "%.1f deg");
        moved |= ImGui::SliderFloat("sun azimuth", &azimuth, -180.f, 180.f, "%.0f deg");
        if (moved) {
            const float el = glm::radians(elevation), az = glm::radians(azimuth);
            e.sun_direction = vec3(std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az));
            act.environment_changed = true;
        }
        float irradiance = max_component(e.sun_irradiance);
        if (ImGui::DragFloat("sun irradiance", &irradiance, 0.01f * std::max(irradiance, 0.1f), 0.f, 1e6f, "%.3g")) {
            e.sun_irradiance = vec3(std::max(irradiance, 0.f));
            act.environment_changed = true;
        }
        act.environment_changed |= ImGui::SliderFloat("sun radius", &e.sun_angular_radius_deg, 0.05f, 10.f, "%.2f deg",
                                                      ImGuiSliderFlags_Logarithmic);
    }
    // The global medium (docs/media.md): coefficients per scene unit, per channel; an edit restarts the accumulation.
    HomogeneousMedium& f = state.fog;
    bool fog_edit = ImGui::DragFloat3("fog scattering", &f.sigma_s.x, 0.002f, 0.f, 1e3f, "%.3g");
    fog_edit |= ImGui::DragFloat3("fog absorption", &f.sigma_a.x, 0.002f, 0.f, 1e3f, "%.3g");
    fog_edit |= ImGui::SliderFloat("fog g", &f.g, -kMaxMediumG, kMaxMediumG, "%.2f");
    if (fog_edit) {
        // Typed values bypass the drag's bounds: keep the coefficients non-negative and finite, |g| <= kMaxMediumG.
        f.sigma_s = glm::clamp(f.sigma_s, vec3(0.f), vec3(1e3f));
        f.sigma_a = glm::clamp(f.sigma_a, vec3(0.f), vec3(1e3f));
        f.g = std::isfinite(f.g) ? std::clamp(f.g, -kMaxMediumG, kMaxMediumG) : 0.f;
        if (!is_finite(f.sigma_s)) f.sigma_s = vec3(0.f);
        if (!is_finite(f.sigma_a)) f.sigma_a = vec3(0.f);
        act.environment_changed = true;
    }
}

// The light groups' live mix (docs/light-groups.md): per group an intensity, a colour, solo and mute. The film
// keeps the groups apart, so a change re-mixes the image on display without restarting the accumulation.
void Panel::light_mix(ViewState& state, const PanelFacts& facts, PanelActions& act) {
    if (facts.snapshot) act.light_mix_changed |= sync_light_mix(state.light_mix, facts.snapshot->light_groups);
    if (state.light_mix.empty()) return;
    ImGui::TextUnformatted("Light groups (live mix, no restart)");
    for (size_t i = 0; i < state.light_mix.size(); ++i) {
        LightMixEntry& g = state.light_mix[i];
        ImGui::PushID(int(i));
        act.light_mix_changed |= ImGui::Checkbox("S", &g.solo);
        ImGui::SameLine();
        act.light_mix_changed |= ImGui::Checkbox("M", &g.mute);
        ImGui::SameLine();
        act.light_mix_changed |=
            ImGui::ColorEdit3("##colour", &g.colour.x, ImGuiColorEditFlags_NoInputs | ImGuiColorEditFlags_Float);
        ImGui::SameLine();
        act.light_mix_changed |=
            ImGui::SliderFloat(g.name.c_str(), &g.intensity, 0.f, 100.f, "%.3g", ImGuiSliderFlags_Logarithmic);
        ImGui::PopID();
    }
    if (ImGui::Button("Reset mix")) {
        for (LightMixEntry& g : state.light_mix) g = LightMixEntry{g.name};
        act.light_mix_changed = true;
    }
    ImGui::Separator();
}

void Panel::camera(ViewState& state, CameraController& ctl, PanelActions& act) {
    CameraDesc& c = ctl.desc();
    const std::string flags = camera_flags(c);
    ImGui::TextWrapped("%s", flags.c_str());
    if (ImGui::Button("Copy as render flags")) {
        ImGui::SetClipboardText(flags.c_str());
        m_log.line("clipboard %s", flags.c_str());
    }
    act.camera_changed |= ImGui::SliderFloat("fov", &c.vfov_deg, 5.f, 150.f, "%.1f deg");
    const float r = ctl.scene_radius();
    act.camera_changed |= ImGui::SliderFloat("aperture", &c.aperture, 0.f, 0.1f * r, "%.4g");
    act.camera_changed |= ImGui::DragFloat("focus distance", &c.focus_distance, 0.005f * r, 0.f, 100.f * r,
                                           c.focus_distance > 0.f ? "%.4g" : "at target");
    if (ImGui::Button(state.pick_focus ? "Click the image..." : "Focus on a point")) state.pick_focus = true;
    ImGui::SameLine();
    ImGui::TextDisabled("(or G under the cursor)");
    ImGui::SliderFloat("fly speed", &ctl.fly_speed, 1e-3f * r, 10.f * r, "%.3g/s", ImGuiSliderFlags_Logarithmic);
    if (ImGui::Button("Frame all (F)")) act.frame_all = true;
    ImGui::SameLine();
    if (ImGui::Button("Reset (R)")) act.reset_camera = true;
    ImGui::TextDisabled(
        "orbit: left drag, pan: middle or shift+left,\ndolly: scroll, fly: WASD/QE,\n"
        "double-click: orbit about a point");
}

void Panel::bookmarks(ViewState& state, PanelActions& act) {
    ImGui::Separator();
    ImGui::TextDisabled("bookmarks (saved with the scene file)");
    for (size_t i = 0; i < state.bookmarks.size(); ++i) {
        ImGui::PushID(int(i));
        if (ImGui::Button("Go")) act.goto_bookmark = int(i);
        ImGui::SameLine();
        ImGui::TextUnformatted(state.bookmarks[i].name.c_str());
        ImGui::PopID();
    }
    ImGui::SetNextItemWidth(160.f);
    ImGui::InputText("##bookmark", m_bookmark_name, sizeof m_bookmark_name);
    ImGui::SameLine();
    if (ImGui::Button("Save view") && m_bookmark_name[0]) act.save_bookmark = m_bookmark_name;
    if (!state.bookmark_status.empty()) status_text(state.bookmark_status, state.bookmark_ok);
}

void Panel::materials(ViewState& state, PanelActions& act) {
    ImGui::TextDisabled("click the image to select a material");
    if (ImGui::BeginListBox("##materials", ImVec2(-FLT_MIN, 6.f * ImGui::GetTextLineHeightWithSpacing()))) {
        for (size_t i = 0; i < state.materials.size(); ++i) {
            const Material& m = state.materials[i];
            char label[160];
            std::snprintf(label, sizeof label, "%s (%s)%s##%zu", m.name.c_str(), bsdf_type_name(m.bsdf),
                          m.has_emission() ? " emits" : "", i);
            const bool selected = int(i) == state.selected_material;
            if (ImGui::Selectable(label, selected)) state.selected_material = int(i);
            if (selected) ImGui::SetItemDefaultFocus();
        }
        ImGui::EndListBox();
    }
    if (state.selected_material >= 0 && size_t(state.selected_material) < state.materials.size()) {
        ImGui::PushID(state.selected_material);
        act.materials_changed |= edit_material(state.materials[size_t(state.selected_material)]);
        ImGui::PopID();
    }
}

void Panel::scene(ViewState& state, PanelActions& act) {
    if (m_scene_path[0] == 0 || state.scene_path != m_field_scene_path) {  // at start, or a scene was dropped
        std::snprintf(m_scene_path, sizeof m_scene_path, "%s", state.scene_path.c_str());
        m_field_scene_path = state.scene_path;
    }
    ImGui::SetNextItemWidth(-FLT_MIN);
    const bool entered =
        ImGui::InputText("##scene", m_scene_path, sizeof m_scene_path, ImGuiInputTextFlags_EnterReturnsTrue);
    log_widget("scene_path");
    ImGui::BeginDisabled(state.scene_loading);
    const bool clicked = ImGui::Button(state.scene_loading ? "Loading..." : "Load (.json, .obj, .gltf, .glb)");
    ImGui::EndDisabled();
    if ((clicked || entered) && !state.scene_loading) {
        state.scene_path = m_scene_path;
        act.load_scene = true;
    }
    if (!state.scene_status.empty()) status_text(state.scene_status, state.scene_ok);
}

}  // namespace pv::ui
