// core/load/start_view.h: the view a scene without a camera starts from (pathview render and view alike, through
// load_scene): inside an interior (a room, an atrium, a church), outside an object. The rule is in start_view.cpp.
#pragma once

#include "core/scene/scene.h"

namespace pv {

// What choose_start_view found, for tests and diagnostics.
struct StartView {
    CameraDesc camera;    // the start view
    bool inside = false;  // an interior: camera.eye inside the bounds; else the outside framing, framing_camera()
    // The best candidate eye's probes: the share of its directions that hit a surface (horizontal and downward ones),
    // the share of its hits on front faces, and its mean distance to the surfaces hit, over the bounds' diagonal.
    float closed = 0.f, front = 0.f, openness = 0.f;
    // The share of the candidate eyes outside solids that are enclosed.
    float enclosed_share = 0.f;
    // Inside, and every probe from the eye (upward ones too) hits a surface: a sky reaches it only through gaps
    // or glass (the conference room; an atrium open to the sky is not sealed).
    bool sealed = false;
};

// The start view of `scene` (see start_view.cpp for the rule). Traces rays through a BVH of its own; deterministic.
StartView choose_start_view(const Scene& scene);

}  // namespace pv
