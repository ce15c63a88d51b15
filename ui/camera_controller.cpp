// ui/camera_controller.cpp: navigation maths. Orbit angles are 0.005 rad per pixel (a 600-pixel drag turns about
// 170 degrees), one scroll step dollies by 15% of the distance to the target.
#include "camera_controller.h"

#include <cstdio>
#include <glm/gtc/quaternion.hpp>
#include <string>

namespace pv::ui {
namespace {
constexpr float kRadiansPerPixel = 0.005f;
constexpr float kDollyPerStep = 0.85f;
constexpr float kMinPolarAngle = 0.01f;  // radians kept away from the up vector
}  // namespace

CameraController::CameraController(const CameraDesc& initial, vec3 lo, vec3 hi) : m_initial(initial), m_desc(initial) {
    const float up_len = glm::length(initial.up);
    m_up = up_len > 0.f ? initial.up / up_len : vec3(0.f, 1.f, 0.f);
    m_center = 0.5f * (lo + hi);
    m_radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    fly_speed = m_radius * 0.5f;
}

vec3 CameraController::forward() const { return glm::normalize(m_desc.target - m_desc.eye); }

void CameraController::orbit(vec2 d) {
    vec3 offset = m_desc.eye - m_desc.target;
    const float dist = glm::length(offset);
    if (!(dist > 0.f)) return;
    // Yaw about the world up, then pitch about the camera's right axis, clamped short of the poles.
    offset = glm::angleAxis(-d.x * kRadiansPerPixel, m_up) * offset;
    const vec3 dir = offset / dist;
    const float polar = std::acos(glm::clamp(glm::dot(dir, m_up), -1.f, 1.f));
    const float new_polar = glm::clamp(polar - d.y * kRadiansPerPixel, kMinPolarAngle, kPi - kMinPolarAngle);
    vec3 right = glm::cross(m_up, dir);
    if (glm::length(right) < 1e-6f) right = glm::cross(m_up, vec3(1.f, 0.f, 0.f));
    offset = glm::angleAxis(new_polar - polar, glm::normalize(right)) * offset;  // + turns away from up
    m_desc.eye = m_desc.target + offset;
    m_desc.up = m_up;
}

void CameraController::pan(vec2 d, int viewport_height_px) {
    const vec3 f = forward();
    const vec3 right = glm::normalize(glm::cross(f, m_up));
    const vec3 up = glm::cross(right, f);
    // World units per pixel on the plane through the target.
    const float dist = glm::length(m_desc.target - m_desc.eye);
    const float k =
        2.f * dist * std::tan(0.5f * glm::radians(m_desc.vfov_deg)) / float(std::max(viewport_height_px, 1));
    const vec3 shift = (-d.x * right + d.y * up) * k;
    m_desc.eye += shift;
    m_desc.target += shift;
}

void CameraController::dolly(float steps) {
    const vec3 offset = m_desc.eye - m_desc.target;
    const float dist = glm::length(offset);
    const float new_dist = glm::clamp(dist * std::pow(kDollyPerStep, steps), 1e-4f * m_radius, 100.f * m_radius);
    m_desc.eye = m_desc.target + offset * (new_dist / dist);
}

void CameraController::fly(vec3 move, float seconds) {
    const vec3 f = forward();
    const vec3 right = glm::normalize(glm::cross(f, m_up));
    const vec3 shift = (move.x * right + move.y * m_up + move.z * f) * (fly_speed * seconds);
    m_desc.eye += shift;
    m_desc.target += shift;
}

void CameraController::frame_all() {
    // As Scene::framing_camera: the bounding sphere fits the vertical field of view, with a 5% margin.
    const float dist = m_radius / std::sin(0.5f * glm::radians(m_desc.vfov_deg)) * 1.05f;
    const vec3 f = forward();
    m_desc.target = m_center;
    m_desc.eye = m_center - f * dist;
}

void CameraController::reset() { m_desc = m_initial; }

void CameraController::retarget(vec3 point) {
    if (glm::length(point - m_desc.eye) > 1e-6f * m_radius) m_desc.target = point;
}

void CameraController::focus_on(vec3 point) {
    // Camera::generate puts the plane of focus at focus_distance along the view direction.
    m_desc.focus_distance = std::max(glm::dot(point - m_desc.eye, forward()), 1e-4f * m_radius);
}

std::string camera_flags(const CameraDesc& c) {
    char buf[512];
    int n = std::snprintf(buf, sizeof buf, "--eye %g,%g,%g --target %g,%g,%g --up %g,%g,%g --fov %g", c.eye.x, c.eye.y,
                          c.eye.z, c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.vfov_deg);
    if (c.aperture > 0.f && n > 0 && n < int(sizeof buf))
        std::snprintf(buf + n, sizeof buf - size_t(n), " --aperture %g --focus-distance %g", c.aperture,
                      c.focus_distance);
    return buf;
}

}  // namespace pv::ui
