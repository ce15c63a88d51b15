// core/render/light_groups.h: light groups, the lights whose contributions the film keeps apart so that they can be
// remixed after rendering (docs/light-groups.md). A group is an emissive material (or the group a scene file names
// for it with "light_group"), a glTF punctual light, the sky or the sun; at most kMaxLightGroups, the rest share
// the last one, "other". Every path's contribution is credited to the group of the light that produced it (found by
// a BSDF-sampled ray or by next-event estimation), so the groups' images add up to the image.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/math.h"
#include "core/image/film.h"
#include "core/scene/bsdf.h"
#include "core/scene/environment.h"
#include "core/scene/scene.h"

namespace pv {

constexpr int kMaxLightGroups = 16;
// A light sample's group when it comes from the environment: the path tracer splits it between the sky and the
// sun by direction (one light for MIS, two groups).
constexpr uint8_t kEnvironmentGroup = 0xFF;

struct LightGroups {
    std::vector<std::string> names;  // one per group, in order
    std::vector<uint8_t> material;   // per material: its group (0 for materials that do not emit)
    std::vector<uint8_t> punctual;   // per punctual light
    uint8_t sky = 0, sun = 0;        // the environment's parts (0 when they do not shine)
    int count() const { return int(names.size()); }
    // More than one group: only then does the film keep per-group sums (one group is the image itself).
    bool active() const { return names.size() > 1; }
    // The group named `name`, or -1.
    int find(const std::string& name) const;
};

// The groups of a scene with these materials and environment: emissive materials in material order (by their
// light_group, else their name; materials of one name share a group), then the punctual lights (by name), then
// the sky and the sun when they shine. A scene with no light at all has one group, "other".
LightGroups make_light_groups(const Scene& scene, const std::vector<Material>& materials,
                              const Environment& environment);

}  // namespace pv
