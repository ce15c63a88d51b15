// core/camera.cpp: pinhole and thin-lens ray generation.
#include "core/camera.h"

#include "core/error.h"
#include "core/warp.h"

namespace pv {

Camera::Camera(const CameraDesc& desc, int width, int height) : m_desc(desc), m_width(width), m_height(height) {
    const vec3 fwd = desc.target - desc.eye;
    if (!(glm::length(fwd) > 0.f) || !is_finite(fwd)) throw Error("camera: eye and target must differ and be finite");
    m_forward = glm::normalize(fwd);
    vec3 right = glm::cross(m_forward, desc.up);
    if (!(glm::length(right) > 1e-6f))
        right = glm::cross(m_forward, std::fabs(m_forward.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0));
    m_right = glm::normalize(right);
    m_up = glm::cross(m_right, m_forward);
    if (!(desc.vfov_deg > 0.f && desc.vfov_deg < 180.f)) throw Error("camera: fov must be in (0, 180) degrees");
    m_tan_half = std::tan(0.5f * glm::radians(desc.vfov_deg));
    m_aspect = static_cast<float>(width) / static_cast<float>(height);
    m_focus = desc.focus_distance > 0.f ? desc.focus_distance : glm::length(fwd);
}

Ray Camera::generate(vec2 film, vec2 u_lens) const {
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
