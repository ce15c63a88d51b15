// tests/render/test_punctual_lights.cpp: glTF KHR_lights_punctual lights by next-event estimation. A Lambertian plane
// of albedo rho under a light reflects L = rho E / pi, E the irradiance the light gives: I cos(theta) / d^2 for a point
// light (times the extension's range falloff clamp(1 - (d / range)^4, 0, 1)^2), the same times the cone's smooth step
// t^2, t = clamp((cos - cos_outer) / (cos_inner - cos_outer), 0, 1), for a spot, and I cos(theta) for a
// directional light, which gives the same picture as a sun of that irradiance. A camera with a narrow field of view
// looks at one point, so the image is that one radiance (the plane is alone: no interreflection).
// Test kinds: analytic
#include <gtest/gtest.h>

#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

constexpr float kRho = 0.5f;

std::shared_ptr<Scene> plane_with(const std::vector<PunctualLight>& lights) {
    auto s = std::make_shared<Scene>();
    Material m;
    m.bsdf = Lambertian{vec3(kRho)};
    const uint32_t mat = test::add_material(*s, m);
    test::add_quad(*s, vec3(-10, -10, 0), vec3(10, -10, 0), vec3(10, 10, 0), vec3(-10, 10, 0), mat);
    s->punctual_lights = lights;
    return s;
}

// The mean radiance seen at point (x, y, 0) of the plane, looked at from straight above.
double radiance_at(std::shared_ptr<Scene> s, float x, float y) {
    CameraDesc cam;
    cam.eye = vec3(x, y, 0.5f);
    cam.target = vec3(x, y, 0.f);
    cam.up = vec3(0, 1, 0);
    cam.vfov_deg = 0.05f;  // a spot of 0.4 mm: the irradiance varies by less than 1e-4 over it
    RenderSettings rs;
    rs.sampler = SamplerKind::Independent;
    const Film f = test::render_with_renderer(s, cam, rs, 4, 4, 4);
    return test::PixelStats::from_film(f).total_mean();
}

TEST(PunctualLights, PointLightGivesTheClosedFormIrradianceWithItsRangeFalloff) {
    PunctualLight l;
    l.type = PunctualLight::Type::Point;
    l.position = vec3(0.3f, 0.f, 1.f);
    l.intensity = vec3(2.f);
    const double d2 = 0.09 + 1.0, cos_t = 1.0 / std::sqrt(d2);
    const double expected = kRho / kPi * 2.0 * cos_t / d2;
    EXPECT_NEAR(radiance_at(plane_with({l}), 0, 0), expected, 1e-3 * expected);
    l.range = 2.f;
    const double falloff = std::pow(std::clamp(1.0 - std::pow(d2 / 4.0, 2.0), 0.0, 1.0), 2.0);
    EXPECT_NEAR(radiance_at(plane_with({l}), 0, 0), expected * falloff, 1e-3 * expected);
    // Two lights add.
    PunctualLight far = l;
    far.range = 0.f;
    EXPECT_NEAR(radiance_at(plane_with({l, far}), 0, 0), expected * (1.0 + falloff), 2e-3 * expected);
}

TEST(PunctualLights, SpotLightsConeAndSmoothFalloff) {
    PunctualLight l;
    l.type = PunctualLight::Type::Spot;
    l.position = vec3(0.f, 0.f, 1.f);
    l.direction = vec3(0.f, 0.f, -1.f);
    l.intensity = vec3(3.f);
    l.inner_cone_rad = 0.2f;
    l.outer_cone_rad = 0.4f;
    const auto s = plane_with({l});
    for (const double angle : {0.1, 0.3, 0.5}) {
        const double x = std::tan(angle), d2 = 1.0 + x * x, c = std::cos(angle);
        const double t = std::clamp((c - std::cos(0.4)) / (std::cos(0.2) - std::cos(0.4)), 0.0, 1.0);
        const double expected = kRho / kPi * 3.0 * c / d2 * t * t;
        EXPECT_NEAR(radiance_at(s, float(x), 0.f), expected, 2e-3 * 3.0 * kRho / kPi) << "at " << angle << " rad";
    }
}

TEST(PunctualLights, DirectionalLightMatchesTheSunOfTheSameIrradiance) {
    PunctualLight l;
    l.type = PunctualLight::Type::Directional;
    l.direction = glm::normalize(vec3(0.f, -0.6f, -0.8f));  // travelling down and toward -y: cos(theta) = 0.8
    l.intensity = vec3(5.f);
    const double expected = kRho / kPi * 5.0 * 0.8;
    EXPECT_NEAR(radiance_at(plane_with({l}), 0, 0), expected, 1e-3 * expected);
    // The sun of irradiance 5 in the same direction (a small disk, sampled): the same radiance within its noise.
    auto sun = plane_with({});
    sun->environment.sun_direction = -l.direction;
    sun->environment.sun_irradiance = vec3(5.f);
    sun->environment.sun_angular_radius_deg = 0.27f;
    EXPECT_NEAR(radiance_at(sun, 0, 0), expected, 1e-2 * expected);
}

}  // namespace
}  // namespace pv
