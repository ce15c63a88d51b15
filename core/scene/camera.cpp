// core/scene/camera.cpp: the camera basis from its description (generate() is inline in camera.h).
#include "core/scene/camera.h"

#include "core/base/error.h"

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

}  // namespace pv
