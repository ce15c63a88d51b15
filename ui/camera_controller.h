// ui/camera_controller.h: orbit / pan / dolly / fly navigation that edits a CameraDesc. World units are the
// scene's; the orbit turns about the world up vector of the initial camera and stays clear of the poles.
// Pixel deltas are window pixels, x to the right and y down.
#pragma once

#include "core/scene/scene.h"

namespace pv::ui {

class CameraController {
public:
    // `initial` is what reset() returns to; the bounds set frame_all() and the default fly speed.
    CameraController(const CameraDesc& initial, vec3 bounds_lo, vec3 bounds_hi);

    void orbit(vec2 delta_px);  // about the target
    void pan(vec2 delta_px,
             int viewport_height_px);    // target and eye move together; the point under the cursor follows it
    void dolly(float steps);             // scroll steps: > 0 moves towards the target
    void fly(vec3 move, float seconds);  // move: x right, y up, z forward, each in [-1, 1]
    void frame_all();                    // the whole scene in view, same direction
    void reset();
    void retarget(vec3 point);  // orbit about `point`; the eye stays
    void focus_on(vec3 point);  // thin-lens focus plane through `point`

    const CameraDesc& desc() const { return m_desc; }
    CameraDesc& desc() { return m_desc; }  // for the panel's fov / aperture / focus edits
    float fly_speed = 1.f;                 // scene units per second
    float scene_radius() const { return m_radius; }

private:
    vec3 forward() const;
    CameraDesc m_initial, m_desc;
    vec3 m_up{0.f, 1.f, 0.f};
    vec3 m_center{0.f};
    float m_radius = 1.f;
};

// The camera as `pathview render` flags: --eye x,y,z --target x,y,z --up x,y,z --fov F [--aperture --focus-distance].
std::string camera_flags(const CameraDesc& c);

}  // namespace pv::ui
