// ui/light_mix.h: the Light section's live mix of light groups (docs/light-groups.md): per group an intensity, a
// colour, mute and solo, turned into the gains the ProgressiveRenderer mixes the film's groups with (no restart).
// Window-free (tests/gui/test_ui_rooms.cpp).
#pragma once

#include <string>
#include <vector>

#include "core/image/film.h"

namespace pv::ui {

struct LightMixEntry {
    std::string name;
    float intensity = 1.f;
    vec3 colour{1.f};
    bool mute = false;
    bool solo = false;
};

// The gains of a mix: intensity x colour; 0 for a muted group, and while any group is soloed, for every group not
// soloed.
LightGains light_mix_gains(const std::vector<LightMixEntry>& mix);
// Makes `mix` list the groups `names` (those of the snapshot on screen): when the names changed (another scene,
// or an edit that changed what emits), every entry starts again at gain 1. Returns whether it changed the mix.
bool sync_light_mix(std::vector<LightMixEntry>& mix, const std::vector<std::string>& names);

}  // namespace pv::ui
