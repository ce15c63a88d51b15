// tests/render/test_equiangular.cpp: single scattering from a point light in an infinite isotropic medium (issue 38,
// equiangular sampling). A camera ray o + t d (t >= 0) in a medium filling all space (sigma_t = sigma_a + sigma_s,
// isotropic phase 1/(4 pi)) passes a point light of intensity I at distance h from its line, the foot of the
// perpendicular at t = delta. The radiance scattered once toward o is
//   L = integral_0^inf exp(-sigma_t t) sigma_s / (4 pi) I exp(-sigma_t r) / r^2 dt,  r = |o + t d - c|,
// and with t = delta + h tan(theta) (dt / r^2 = d theta / h, r = h / cos(theta)) it is the integral of a smooth
// function over a finite interval:
//   L = sigma_s I / (4 pi h) integral_{theta_a}^{pi/2} exp(-sigma_t (delta + h tan(theta) + h / cos(theta))) d theta,
// theta_a = atan(-delta / h), evaluated by Simpson's rule in double to 1e-9. The walker with max_depth 1 computes
// exactly this (the camera segment's scattering events and its equiangular samples; the next event would be a second
// bounce), so its mean must match within a confidence interval (equiangular and distance sampling combined by MIS),
// for a light ahead of the ray's origin and one behind it.
// Test kinds: analytic
#include <gtest/gtest.h>

#include <cmath>

#include "core/render/integrator.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

double single_scattering(double sigma_s, double sigma_t, double intensity, double delta, double h) {
    const double a = std::atan2(-delta, h), b = 0.5 * kPi;
    auto f = [&](double th) {
        if (th >= b) return 0.0;
        return std::exp(-sigma_t * (delta + h * std::tan(th) + h / std::cos(th)));
    };
    constexpr int n = 200000;
    const double step = (b - a) / n;
    double sum = f(a) + f(b);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(a + i * step);
    return sigma_s * intensity / (4.0 * kPi * h) * sum * step / 3.0;
}

TEST(EquiangularAnalytic, SingleScatteringFromAPointLightInAnInfiniteMedium) {
    const float sigma_s = 0.3f, sigma_a = 0.2f;
    // The light ahead of the ray's origin and behind it (the segment starts past the light's foot).
    const vec3 lights[] = {vec3(0.4f, 0.3f, -2.f), vec3(0.1f, -0.5f, 1.f)};
    for (size_t i = 0; i < std::size(lights); ++i) {
        auto scene = std::make_shared<Scene>();
        // The only surface: a small black quad behind the ray's origin, so the ray is unbounded.
        Material black;
        black.bsdf = Lambertian{vec3(0.f)};
        test::add_quad(*scene, vec3(-1.f, -1.f, 1000.f), vec3(1.f, -1.f, 1000.f), vec3(1.f, 1.f, 1000.f),
                       vec3(-1.f, 1.f, 1000.f), test::add_material(*scene, black));
        scene->environment.background = vec3(0.f);
        scene->fog = HomogeneousMedium{vec3(sigma_a), vec3(sigma_s), 0.f};
        PunctualLight light;
        light.type = PunctualLight::Type::Point;
        light.position = lights[i];
        light.intensity = vec3(10.f);
        scene->punctual_lights.push_back(light);
        const test::Tracer ts(scene);
        Ray ray;
        ray.o = vec3(0.f);
        ray.d = vec3(0.f, 0.f, -1.f);
        const double delta = -double(lights[i].z);
        const double h = std::hypot(double(lights[i].x), double(lights[i].y));
        const double expected = single_scattering(sigma_s, sigma_s + sigma_a, 10.0, delta, h);
        RenderSettings s;
        s.sampler = SamplerKind::Independent;
        s.max_depth = 1;
        Sampler sampler(9, SamplerKind::Independent);
        test::Moments mom;
        PathCounters counters;
        for (uint32_t n = 0; n < 100000; ++n) {
            sampler.start(uvec2(uint32_t(i), 0u), n);
            mom.add(trace_path(ts, s, ray, sampler, counters).x);
        }
        const double k = test::sidak_k(double(std::size(lights)));
        EXPECT_LE(std::fabs(mom.mean - expected), k * mom.stderr_of_mean())
            << "light " << i << ": mean " << mom.mean << ", expected " << expected << ", stderr "
            << mom.stderr_of_mean();
        // Equiangular sampling cancels the inverse-square peak: the standard deviation stays of the mean's order.
        EXPECT_LT(std::sqrt(mom.variance()), 3.0 * expected)
            << "light " << i << ": stddev " << std::sqrt(mom.variance());
    }
}

}  // namespace
}  // namespace pv
