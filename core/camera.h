// core/camera.h: generates primary rays. Film coordinates are continuous pixels: (0,0) is the top-left corner
// of the image, (width, height) the bottom-right. Right-handed world; the camera looks from eye to target.
#pragma once

#include "core/scene.h"

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

}  // namespace pv
