// ui/panel_render.cpp: the panel's rendering sections: progress, convergence, estimator, display.
#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string_view>
#include <type_traits>

#include "panel.h"
#include "panel_widgets.h"

namespace pv::ui {
namespace {

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

// One widget for a field of the settings table: a checkbox for on|off, a combo of its words (each value once, by its
// first word), or a number kept in the table's range; the table's help is the tooltip. True when the value changed.
template <class Field>
bool setting_widget(RenderSettings& s, const Field& f) {
    using T = std::decay_t<decltype(s.*f.member)>;
    T& value = s.*f.member;
    bool changed = false;
    if constexpr (std::is_same_v<T, bool>) {
        changed = ImGui::Checkbox(f.label, &value);
    } else if constexpr (std::is_enum_v<T>) {
        constexpr int kMax = 8;
        const char* words[kMax];
        T values[kMax];
        int n = 0, current = 0;
        for (size_t i = 0; i < f.name_count && n < kMax; ++i) {
            if (std::find(values, values + n, f.names[i].value) != values + n) continue;
            if (f.names[i].value == value) current = n;
            values[n] = f.names[i].value;
            words[n++] = f.names[i].name;
        }
        ImGui::SetNextItemWidth(160.f);
        if (ImGui::Combo(f.label, &current, words, n)) {
            value = values[current];
            changed = true;
        }
    } else {
        static_assert(std::is_integral_v<T>, "a numeric setting of the table is an integer");
        int64_t v = int64_t(value);
        const int64_t step = 1;
        ImGui::SetNextItemWidth(140.f);
        if (ImGui::InputScalar(f.label, ImGuiDataType_S64, &v, &step)) {
            const int64_t lo = f.ranged ? int64_t(f.lo) : int64_t(std::numeric_limits<T>::min());
            const int64_t hi = f.ranged ? int64_t(f.hi) : int64_t(std::numeric_limits<T>::max());
            value = T(std::clamp(v, lo, hi));
            changed = true;
        }
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", f.help);
    return changed;
}

}  // namespace

void Panel::progress(ViewState& state, const PanelFacts& facts, PanelActions& act) {
    const Snapshot& s = *facts.snapshot;
    const double secs = std::max(s.seconds, 1e-9);
    ImGui::Text("%u spp   %.1f s   %dx%d%s", s.spp, s.seconds, s.width, s.height,
                facts.level > 1 ? (facts.level == 4 ? " (1/4, moving)" : " (1/2, refining)") : "");
    ImGui::Text("%s samples/s   %.1f Mrays/s", format_si(double(s.paths) / secs).c_str(), s.mrays_per_s);
    ImGui::Text("%.1f ms/pass   UI frame %.1f ms", s.ms_per_pass, facts.frame_ms);
    if (s.dropped) ImGui::TextColored(kWarningColour, "%llu non-finite samples dropped", (unsigned long long)s.dropped);
    const char* status =
        state.paused       ? "paused"
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

// The Estimator section is drawn from the settings table (core/render/settings.h): each field's widget, label and
// tooltip come from its row; a field that needs a switch (MIS needs light sampling) sits indented under it and is
// disabled while that switch is off.
void Panel::estimator(ViewState& state, const PanelFacts& facts, PanelActions& act) {
    RenderSettings& s = state.settings;
    auto draw = [&](const auto& f) {
        act.settings_changed |= setting_widget(s, f);
        log_widget(f.key);
        if (std::string_view(f.key) == "sky_guide" && facts.snapshot && !facts.snapshot->sky_guide.empty())
            ImGui::TextDisabled("  sky guide %s", facts.snapshot->sky_guide.c_str());
    };
    for_each_setting([&](const auto& parent) {
        if (parent.needs) return;
        draw(parent);
        bool on = true;
        if constexpr (std::is_same_v<std::decay_t<decltype(s.*parent.member)>, bool>) on = s.*parent.member;
        ImGui::Indent();
        ImGui::BeginDisabled(!on);
        for_each_setting([&](const auto& f) {
            if (f.needs && std::string_view(f.needs) == parent.key) draw(f);
        });
        ImGui::EndDisabled();
        ImGui::Unindent();
    });
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
    view_transform(state);
    int view = static_cast<int>(d.view);
    if (ImGui::Combo("view", &view, "colour\0relative error (1e-3..1, log)\0sample count (0..spp)\0"))
        d.view = View(view);
    log_widget("view");
}

}  // namespace pv::ui
