// ui/panel.cpp: the panel's sections, top to bottom: warnings, progress, convergence, estimator, display,
// snapshot, compare, light, camera (with bookmarks), materials, scene.
#include "panel.h"

#include <imgui.h>

#include <cfloat>
#include <cmath>
#include <cstdio>

#include "core/scene/material_params.h"

namespace pv::ui {
namespace {

const ImVec4 kWarningColour(1.f, 0.75f, 0.3f, 1.f);

// A status line: wrapped, in the warning colour when it reports a failure.
void status_text(const std::string& text, bool ok) {
    if (!ok) ImGui::PushStyleColor(ImGuiCol_Text, kWarningColour);
    ImGui::TextWrapped("%s", text.c_str());
    if (!ok) ImGui::PopStyleColor();
}

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

// Plots log10 values against an evenly spaced log10 x range, with the range in the overlay. The plot keeps its
// size while empty, so the widgets below it do not jump when an accumulation restarts.
void log_log_plot(const char* label, const std::vector<float>& values, float lo, float hi, const char* x_name) {
    const ImVec2 size(ImGui::GetContentRegionAvail().x, 64.f);  // PlotLines takes no negative widths
    char overlay[96];
    if (values.empty())
        std::snprintf(overlay, sizeof overlay, "log relMSE vs log %s: from 2 spp", x_name);
    else
        std::snprintf(overlay, sizeof overlay, "log10 relMSE vs log10 %s, %s = %.3g..%.3g", x_name, x_name,
                      std::pow(10.f, lo), std::pow(10.f, hi));
    static const float kNothing[2] = {0.f, 0.f};
    const bool empty = values.empty();
    ImGui::PlotLines(label, empty ? kNothing : values.data(), empty ? 2 : int(values.size()), 0, overlay,
                     empty ? 0.f : FLT_MAX, empty ? 1.f : FLT_MAX, size);
}

}  // namespace

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

void Panel::progress(ViewState& state, const PanelFacts& facts, PanelActions& act) {
    const Snapshot& s = *facts.snapshot;
    const double secs = std::max(s.seconds, 1e-9);
    ImGui::Text("%u spp   %.1f s   %dx%d%s", s.spp, s.seconds, s.width, s.height,
                facts.level > 1 ? (facts.level == 4 ? " (1/4, moving)" : " (1/2, refining)") : "");
    ImGui::Text("%s samples/s   %.1f Mrays/s", format_si(double(s.paths) / secs).c_str(), s.mrays_per_s);
    ImGui::Text("%.1f ms/pass   UI frame %.1f ms", s.ms_per_pass, facts.frame_ms);
    if (s.dropped) ImGui::TextColored(kWarningColour, "%llu non-finite samples dropped", (unsigned long long)s.dropped);
    const char* status =
        facts.minimised    ? "minimised: paused"
        : state.paused     ? "paused"
        : s.target_reached ? (s.active_fraction == 0.0 ? "noise threshold reached: stopped" : "target reached: stopped")
                           : "rendering";
    // Always said: the denoised image or the raw accumulation (N toggles; the errors are the raw estimator's).
    ImGui::TextWrapped("status: %s; shown: %s", status, shown_image(state, facts.snapshot).c_str());
    log_widget("status");
    ImGui::SetNextItemWidth(100.f);
    if (ImGui::InputInt("target spp", &state.target_spp, 16, 256)) {
        state.target_spp = std::max(state.target_spp, 0);
        act.control_changed = true;
    }
    ImGui::SetNextItemWidth(100.f);
    if (ImGui::InputFloat("target seconds", &state.target_seconds, 5.f, 60.f, "%.0f")) {
        state.target_seconds = std::max(state.target_seconds, 0.f);
        act.control_changed = true;
    }
    if (ImGui::Checkbox("adaptive sampling", &state.adaptive.allocate)) act.settings_changed = true;
    log_widget("adaptive");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Each region takes samples in proportion to its relative error per sample over the root of its cost in\n"
            "rays, both estimated from %u pilot passes (and a few later ones) that never steer their own samples:\n"
            "unbiased. 'spp' counts passes, which the noisiest pixels all take; the sample-count view shows where\n"
            "they went. Off by default: it pays only where few pixels carry the noise (docs/convergence.md).",
            kPilotPasses);
    if (state.adaptive.allocate && s.spp > 0 && s.width > 0 && s.height > 0) {
        ImGui::SameLine();
        ImGui::TextDisabled("mean %.1f spp", double(s.paths) / (double(s.width) * s.height));
    }
    ImGui::SetNextItemWidth(100.f);
    if (ImGui::InputFloat("stop at noise threshold", &state.adaptive.noise_threshold, 0.005f, 0.05f, "%.3f")) {
        state.adaptive.noise_threshold = std::clamp(state.adaptive.noise_threshold, 0.f, 1.f);
        act.settings_changed = true;  // pixels that stopped never restart: a new threshold needs a new accumulation
    }
    if (state.adaptive.enabled()) {
        if (s.seconds_to_threshold >= 0.0)
            ImGui::Text("%.1f%% of pixels active   at most about %.0f s left", 100.0 * s.active_fraction,
                        s.seconds_to_threshold);
        else
            ImGui::Text("%.1f%% of pixels active", 100.0 * s.active_fraction);
    }
    if (ImGui::Button(state.paused ? "Resume" : "Pause")) {
        state.paused = !state.paused;
        act.control_changed = true;
    }
    log_widget("pause");
    ImGui::SameLine();
    if (ImGui::Button("Restart")) act.restart = true;
}

void Panel::convergence(const PanelFacts& facts) {
    const Snapshot& s = *facts.snapshot;
    const ConvergenceHistory& h = *facts.history;
    if (s.rel_mse > 0.0 && h.size() >= 4)
        ImGui::Text("est. relMSE (raw) %.2e  slope %.2f (ideal -1)", s.rel_mse, h.slope_vs_spp());
    else if (s.rel_mse > 0.0)
        ImGui::Text("est. relMSE (raw) %.3e", s.rel_mse);
    else
        ImGui::TextDisabled("est. relMSE: from 2 spp (even/odd halves)");
    float lo = 0.f, hi = 0.f;
    const std::vector<float> by_time = h.log_log_by_seconds(64, lo, hi);
    log_log_plot("##time", by_time, lo, hi, "s");
    const std::vector<float> by_spp = h.log_log_by_spp(64, lo, hi);
    log_log_plot("##spp", by_spp, lo, hi, "spp");
    // Against B (Compare section): the true relMSE when B is a reference, next to the estimate above.
    if (!facts.compare || !facts.compare->has_b()) return;
    const Compare& c = *facts.compare;
    if (const auto r = c.rel_mse()) {
        if (c.rel_mse_denoised() >= 0.0)
            ImGui::Text("relMSE vs B %.3e   denoised %.3e", *r, c.rel_mse_denoised());
        else
            ImGui::Text("relMSE vs B %.3e", *r);
    } else {
        ImGui::TextDisabled("relMSE vs B: when A is %dx%d like B", c.b().width, c.b().height);
    }
    const std::vector<float> vs_b = c.history().log_log_by_seconds(64, lo, hi);
    char overlay[96];
    if (vs_b.empty())
        std::snprintf(overlay, sizeof overlay, "relMSE vs B against time: from 2 points");
    else
        std::snprintf(overlay, sizeof overlay, "log10 relMSE vs B against log10 s, s = %.3g..%.3g", std::pow(10.f, lo),
                      std::pow(10.f, hi));
    static const float kNothing[2] = {0.f, 0.f};
    ImGui::PlotLines("##vs_b", vs_b.empty() ? kNothing : vs_b.data(), vs_b.empty() ? 2 : int(vs_b.size()), 0, overlay,
                     vs_b.empty() ? 0.f : FLT_MAX, vs_b.empty() ? 1.f : FLT_MAX,
                     ImVec2(ImGui::GetContentRegionAvail().x, 48.f));
}

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

void Panel::estimator(ViewState& state, const PanelFacts& facts, PanelActions& act) {
    RenderSettings& s = state.settings;
    act.settings_changed |= ImGui::Checkbox("light sampling (NEE)", &s.light_sampling);
    log_widget("light_sampling");
    ImGui::BeginDisabled(!s.light_sampling);
    act.settings_changed |= ImGui::Checkbox("MIS", &s.mis);
    int light_sampler = static_cast<int>(s.light_sampler);
    if (ImGui::Combo("light sampler", &light_sampler, "power\0tree\0")) {
        s.light_sampler = static_cast<LightSamplerKind>(light_sampler);
        act.settings_changed = true;
    }
    log_widget("light_sampler");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "How an emissive triangle is chosen for a light sample: in proportion to its power, or by a light tree "
            "in proportion to a bound on what it sends to the shading point (scenes of many lights)");
    int guide = static_cast<int>(s.sky_guide);
    if (ImGui::Combo("sky guide", &guide, "off\0on\0auto\0")) {
        s.sky_guide = static_cast<SkyGuideMode>(guide);
        act.settings_changed = true;
    }
    log_widget("sky_guide");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Aim the sky's light samples at the directions a short training pass found unoccluded; auto: where the "
            "training predicts it pays");
    if (facts.snapshot && !facts.snapshot->sky_guide.empty())
        ImGui::TextDisabled("  sky guide %s", facts.snapshot->sky_guide.c_str());
    ImGui::EndDisabled();
    act.settings_changed |= ImGui::Checkbox("Russian roulette", &s.russian_roulette);
    log_widget("rr");
    const int unbounded = RenderSettings{}.max_depth;
    bool is_unbounded = s.max_depth >= unbounded;
    if (ImGui::Checkbox("unbounded depth", &is_unbounded)) {
        s.max_depth = is_unbounded ? unbounded : 8;
        act.settings_changed = true;
    }
    if (!is_unbounded) act.settings_changed |= ImGui::SliderInt("max depth", &s.max_depth, 0, 64);
    int seed = static_cast<int>(s.seed);
    ImGui::SetNextItemWidth(100.f);
    if (ImGui::InputInt("seed", &seed)) {
        s.seed = static_cast<uint32_t>(std::max(seed, 0));
        act.settings_changed = true;
    }
    int sampler = static_cast<int>(s.sampler);
    if (ImGui::Combo("sampler", &sampler, "independent\0Sobol (Owen-scrambled)\0")) {
        s.sampler = static_cast<SamplerKind>(sampler);
        act.settings_changed = true;
    }
}

void Panel::lighting(ViewState& state, PanelActions& act) {
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

void Panel::display(ViewState& state, const PanelFacts& facts) {
    DisplayParams& d = state.display;
    ImGui::Checkbox("denoised display (N; off: raw accumulation)", &d.denoise);
    log_widget("denoise");
    if (d.denoise && facts.snapshot) {
        const Snapshot& s = *facts.snapshot;
        if (s.denoised.empty())
            ImGui::TextDisabled("denoising ...");
        else
            ImGui::TextWrapped("a-trous, %u of %u spp, %.0f ms a pass (the errors above are the raw estimator's)",
                               s.denoised_spp, s.spp, s.denoise_ms);
    }
    ImGui::SliderFloat("exposure", &d.exposure, -10.f, 10.f, "%+.1f stops");
    int tone = static_cast<int>(d.tone_map);
    if (ImGui::Combo("tone map", &tone, "clamp\0Reinhard (luminance)\0ACES filmic\0")) d.tone_map = ToneMap(tone);
    int view = static_cast<int>(d.view);
    if (ImGui::Combo("view", &view, "colour\0relative error (1e-3..1, log)\0sample count (0..spp)\0"))
        d.view = View(view);
    log_widget("view");
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
    ImGui::TextDisabled("to %s", state.snapshot_dir.c_str());
    if (ImGui::Button("Save resumable EXR")) act.save_resumable = true;
    log_widget("save_resumable");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "The accumulation's exact per-pixel sums (a partial render):\n"
            "pathview render --resume FILE --spp N -o OUT.exr adds N samples.");
    if (!state.snapshot_status.empty()) status_text(state.snapshot_status, state.snapshot_ok);
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
