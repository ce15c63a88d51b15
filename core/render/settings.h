// core/render/settings.h: the estimator's switches (RenderSettings) and their one table of fields. Every use that
// goes over all the fields, equality, describe() and its parse (the partial renders' pathview:settings), and the
// command line's options (app/common.cpp), walks for_each_setting, so adding a setting is one line of the table
// (after yocto-gl's trace_params, whose names and labels sit next to the fields).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>

#include "core/base/text.h"
#include "core/sampling/sampler.h"

namespace pv {

// --sky-guide: off, on, or auto (trained, then used where the training predicts it pays; core/render/sky_guide.h).
enum class SkyGuideMode : uint8_t { Off, On, Auto };
inline constexpr NamedValue<SkyGuideMode> kSkyGuideNames[] = {
    {"off", SkyGuideMode::Off}, {"on", SkyGuideMode::On}, {"auto", SkyGuideMode::Auto}};

// --light-sampler: how an emissive triangle is chosen. Power: in proportion to its power, wherever the shading point
// (an alias table). Tree: by a light tree (core/render/light_tree.h) in proportion to a bound on its contribution at
// the shading point and normal.
enum class LightSamplerKind : uint8_t { Power, Tree };
inline constexpr NamedValue<LightSamplerKind> kLightSamplerNames[] = {{"power", LightSamplerKind::Power},
                                                                      {"tree", LightSamplerKind::Tree}};
inline const char* light_sampler_name(LightSamplerKind k) { return name_of(kLightSamplerNames, k); }

// A switch's words.
inline constexpr NamedValue<bool> kOnOffNames[] = {{"on", true}, {"off", false}};

// The estimator's switches, as plain data. Defaults are unbiased in practice (depth 1024 is never reached
// with roulette on: survival falls geometrically with throughput).
struct RenderSettings {
    bool light_sampling = true;  // next-event estimation over emissive triangles, sky and sun
    bool mis = true;             // power-heuristic MIS between light and BSDF sampling (needs light_sampling)
    bool russian_roulette = true;
    int max_depth = 1024;
    uint32_t seed = 0;
    // Owen-scrambled Sobol: measured better at equal time on the Cornell box (BENCHMARKS.md sections 1 and 5).
    SamplerKind sampler = SamplerKind::Sobol;  // see core/sampling/sampler.h
    // Next-event estimation of the sky guided toward the directions a training pre-pass found unoccluded
    // (core/render/sky_guide.h); only where the sky shines and the scene has no portals. Auto by default: the training
    // predicts whether the guide pays for its cost (it halves the error of a room lit by the sky through a window,
    // and costs more than it gains on the sun-lit room, Sibenik and the conference room; docs/sky-guide.md).
    SkyGuideMode sky_guide = SkyGuideMode::Auto;
    // How next-event estimation chooses an emissive triangle: by power, or by a light tree at the shading point
    // (core/render/light_tree.h; docs/light-sampling.md has the measurements behind the default).
    LightSamplerKind light_sampler = LightSamplerKind::Power;

    bool operator==(const RenderSettings& o) const;
    bool operator!=(const RenderSettings& o) const { return !(*this == o); }
    // One line for logs and EXR metadata, e.g. "nee=on mis=on rr=on max_depth=1024 seed=0 sampler=independent",
    // then " sky_guide=on" or " sky_guide=auto", then " light_sampler=tree" with the tree (strings from before the
    // guide existed mean it off; a render's settings_as_rendered() resolves auto to on or off).
    std::string describe() const;
};

// One field of RenderSettings: its key in describe() ("key=value"), its command-line flag and help, its label in the
// viewer's Estimator section (the help is the widget's tooltip), the key of a switch it needs on to mean anything
// (none: nullptr), and either its words (a bool or an enum: `names`, the first word of a value being the one
// written) or, for a number, the range the command line and the panel accept. A field whose value is `omitted` is
// left out of describe(), and text without the key means that value (keys added after partial files existed, so
// that those files still read).
template <class T>
struct SettingField {
    const char* key;
    const char* flag;
    const char* help;
    const char* label;
    const char* needs;
    T RenderSettings::*member;
    const NamedValue<T>* names = nullptr;  // with name_count words; none for a number
    size_t name_count = 0;
    bool ranged = false;  // a number the command line checks against [lo, hi]
    T lo{}, hi{};
    std::optional<T> omitted;

    const char* name(T v) const {
        for (size_t i = 0; i < name_count; ++i)
            if (names[i].value == v) return names[i].name;
        return nullptr;
    }
    // The value as describe() writes it: its first word, or the number.
    std::string word(T v) const {
        if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
            return std::to_string(v);
        else
            return name(v);
    }
    std::optional<T> value(const std::string& word) const {
        for (size_t i = 0; i < name_count; ++i)
            if (word == names[i].name) return names[i].value;
        return std::nullopt;
    }
};

namespace settings_detail {
struct Names {  // key, flag, help, panel label, the switch it needs
    const char* key;
    const char* flag;
    const char* help;
    const char* label;
    const char* needs = nullptr;
};
template <class T, size_t N>
constexpr SettingField<T> named(Names n, T RenderSettings::*member, const NamedValue<T> (&names)[N],
                                std::optional<T> omitted = std::nullopt) {
    return {n.key, n.flag, n.help, n.label, n.needs, member, names, N, false, T{}, T{}, omitted};
}
template <class T>
constexpr SettingField<T> number(Names n, T RenderSettings::*member) {
    return {n.key, n.flag, n.help, n.label, n.needs, member};
}
template <class T>
constexpr SettingField<T> number(Names n, T RenderSettings::*member, T lo, T hi) {
    return {n.key, n.flag, n.help, n.label, n.needs, member, nullptr, 0, true, lo, hi, std::nullopt};
}
}  // namespace settings_detail

// The table: calls f(field) for every field of RenderSettings, in describe()'s order.
template <class F>
void for_each_setting(F&& f) {
    using namespace settings_detail;
    using S = RenderSettings;
    f(named({"nee", "--light-sampling", "Next-event estimation: on|off", "light sampling (NEE)"}, &S::light_sampling,
            kOnOffNames));
    f(named({"mis", "--mis", "Multiple importance sampling of light and BSDF samples: on|off", "MIS", "nee"}, &S::mis,
            kOnOffNames));
    f(named({"rr", "--rr", "Russian roulette: on|off", "Russian roulette"}, &S::russian_roulette, kOnOffNames));
    f(number({"max_depth", "--max-depth", "Maximum number of scattering events (0: emitters seen directly only)",
              "max depth"},
             &S::max_depth, 0, 100000));
    f(number({"seed", "--seed", "Random seed (the image depends only on it, not on threads)", "seed"}, &S::seed));
    f(named({"sampler", "--sampler", "Sample generator: independent|sobol (Owen-scrambled, padded)", "sampler"},
            &S::sampler, kSamplerNames));
    // Off is left out: strings from before the guide existed mean it off.
    f(named({"sky_guide", "--sky-guide",
             "Next-event estimation of the sky aimed at the directions a short training pre-pass found "
             "unoccluded (interiors lit through openings): on|off|auto (auto: where the training predicts "
             "it pays for its cost)",
             "sky guide", "nee"},
            &S::sky_guide, kSkyGuideNames, std::optional<SkyGuideMode>(SkyGuideMode::Off)));
    f(named({"light_sampler", "--light-sampler",
             "How next-event estimation chooses an emissive triangle: power (in proportion to its power) or "
             "tree (a light tree: in proportion to a bound on its contribution at the shading point; for "
             "scenes of many lights)",
             "light sampler", "nee"},
            &S::light_sampler, kLightSamplerNames, std::optional<LightSamplerKind>(LightSamplerKind::Power)));
}

inline bool RenderSettings::operator==(const RenderSettings& o) const {
    bool same = true;
    for_each_setting([&](const auto& f) { same = same && this->*f.member == o.*f.member; });
    return same;
}

// describe() read back: nothing unless the text is exactly what describe() writes for the settings it names (every
// key once, in order, words and decimals as written).
std::optional<RenderSettings> settings_from_text(const std::string& text);

}  // namespace pv
