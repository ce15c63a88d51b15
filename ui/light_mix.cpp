// ui/light_mix.cpp: see light_mix.h.
#include "light_mix.h"

#include <algorithm>

namespace pv::ui {

LightGains light_mix_gains(const std::vector<LightMixEntry>& mix) {
    const bool solo = std::any_of(mix.begin(), mix.end(), [](const LightMixEntry& e) { return e.solo; });
    LightGains gains;
    gains.reserve(mix.size());
    for (const LightMixEntry& e : mix)
        gains.push_back(e.mute || (solo && !e.solo) ? vec3(0.f) : std::max(e.intensity, 0.f) * e.colour);
    return gains;
}

bool sync_light_mix(std::vector<LightMixEntry>& mix, const std::vector<std::string>& names) {
    const bool same = mix.size() == names.size() &&
                      std::equal(mix.begin(), mix.end(), names.begin(),
                                 [](const LightMixEntry& e, const std::string& n) { return e.name == n; });
    if (same) return false;
    mix.clear();
    for (const std::string& n : names) mix.push_back(LightMixEntry{n});
    return true;
}

}  // namespace pv::ui
