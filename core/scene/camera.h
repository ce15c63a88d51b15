// core/scene/camera.h: generates primary rays. Film coordinates are continuous pixels: (0,0) is the top-left corner
// of the image, (width, height) the bottom-right. Right-handed world; the camera looks from eye to target.
#pragma once

#include "core/sampling/warp.h"
#include "core/scene/scene.h"

namespace pv {

struct Ray {
    vec3 o{0.f};
    vec3 d{0.f, 0.f, 1.f};
    float tmax = std::numeric_limits<float>::infinity();
};

class Camera {
public:
    Camera() = default;
    Camera(const CameraDesc& desc, int width, int height);

    // A ray through film point `film` (pixels); u_lens picks the point on the thin lens. d is unit length.
    // Inline: called once per sample, and an out-of-line call returns the Ray through memory, which the caller
    // reloaded in other-sized pieces (a store-forwarding stall per sample).
    Ray generate(vec2 film, vec2 u_lens) const;
    // False for a pinhole (aperture 0): generate() then ignores u_lens.
    bool has_lens() const { return m_desc.aperture > 0.f; }
    const CameraDesc& desc() const { return m_desc; }
    int width() const { return m_width; }
    int height() const { return m_height; }

private:
    CameraDesc m_desc;
    int m_width = 1, m_height = 1;
    vec3 m_forward{0, 0, -1}, m_right{1, 0, 0}, m_up{0, 1, 0};
    float m_tan_half = 1.f, m_aspect = 1.f, m_focus = 1.f;
};

inline Ray Camera::generate(vec2 film, vec2 u_lens) const {
    const float sx = (2.f * film.x / static_cast<float>(m_width) - 1.f) * m_tan_half * m_aspect;
    const float sy = (1.f - 2.f * film.y / static_cast<float>(m_height)) * m_tan_half;
    vec3 dir = m_forward + sx * m_right + sy * m_up;
    Ray r;
    if (m_desc.aperture > 0.f) {
        // Thin lens: every ray through the lens point meets the pinhole ray on the plane of focus.
        const vec3 focus_point = m_desc.eye + dir * m_focus;
        const vec2 lens = m_desc.aperture * square_to_disk_concentric(u_lens);
        r.o = m_desc.eye + lens.x * m_right + lens.y * m_up;
        r.d = glm::normalize(focus_point - r.o);
    } else {
        r.o = m_desc.eye;
        r.d = glm::normalize(dir);
    }
    return r;
}

}  // namespace pv
