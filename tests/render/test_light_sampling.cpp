// Emitter triangles sampled by solid angle (core/sampling/spherical_triangle.h, LightSet): the directions follow the
// pdf that LightSet::pdf gives a BSDF-found emitter (chi-square per triangle shape, including a sliver, a triangle seen
// nearly edge-on and a point almost touching one), the solid angle matches a closed form, and both the solid-angle
// and the area rule estimate a triangle's irradiance as Lambert's closed form gives it.
// Test kinds: statistical; unit: SphericalTriangleArea; analytic: SolidAngleIrradiance
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/render/lights.h"
#include "core/sampling/rng.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

struct Tri {
    const char* name;
    vec3 p0, p1, p2;
    vec3 ref;
    bool spherical;  // whether the solid-angle rule applies at ref (else the area rule)
};

const Tri kTris[] = {
    {"regular", vec3(-0.5f, 1.f, -0.3f), vec3(0.6f, 1.f, -0.4f), vec3(0.1f, 1.f, 0.7f), vec3(0.f), true},
    {"sliver", vec3(0.f, 0.f, 0.f), vec3(1.f, 0.f, 0.f), vec3(0.5f, 0.01f, 0.f), vec3(0.5f, 0.f, 0.3f), true},
    {"nearly edge-on", vec3(0.f, 0.f, 0.f), vec3(1.f, 0.f, 0.f), vec3(0.f, 1.f, 0.f), vec3(1.2f, 1.2f, 0.02f), true},
    {"almost touching", vec3(0.f, 0.f, 0.f), vec3(1.f, 0.f, 0.f), vec3(0.f, 1.f, 0.f), vec3(0.3f, 0.3f, 0.01f), true},
    {"far", vec3(0.f, 0.f, 0.f), vec3(0.1f, 0.f, 0.f), vec3(0.f, 0.1f, 0.f), vec3(0.f, 0.f, 20.f), false},
    {"touching", vec3(0.f, 0.f, 0.f), vec3(1.f, 0.f, 0.f), vec3(0.f, 1.f, 0.f), vec3(0.3f, 0.3f, 1e-5f), false},
};

Scene one_emitter(const Tri& t, vec3 emission = vec3(1.f)) {
    Scene scene;
    Material m;
    m.emission = emission;
    m.two_sided_emission = true;
    scene.materials.push_back(m);
    scene.positions = {t.p0, t.p1, t.p2};
    scene.triangles = {uvec3(0, 1, 2)};
    scene.material_ids = {0};
    return scene;
}

// The solid angle of a triangle by Girard's theorem in double (the sum of the spherical angles minus pi).
double girard_solid_angle(const Tri& t) {
    const dvec3 v[3] = {glm::normalize(dvec3(t.p0 - t.ref)), glm::normalize(dvec3(t.p1 - t.ref)),
                        glm::normalize(dvec3(t.p2 - t.ref))};
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
        const dvec3 a = v[i], b = v[(i + 1) % 3], c = v[(i + 2) % 3];
        const dvec3 n1 = glm::normalize(glm::cross(a, b)), n2 = glm::normalize(glm::cross(a, c));
        sum += std::acos(glm::clamp(glm::dot(n1, n2), -1.0, 1.0));
    }
    return sum - M_PI;
}

TEST(SphericalTriangleArea, SolidAngleMatchesGirard) {
    for (const Tri& t : kTris) {
        const double want = girard_solid_angle(t);
        EXPECT_NEAR(spherical_triangle_area(t.ref, t.p0, t.p1, t.p2), want, 1e-4 * want + 1e-7) << t.name;
    }
}

double solid_angle_d(dvec3 ref, dvec3 p0, dvec3 p1, dvec3 p2) {
    const dvec3 a = p0 - ref, b = p1 - ref, c = p2 - ref;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = std::fabs(glm::dot(a, glm::cross(b, c)));
    const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    return std::fabs(2.0 * std::atan2(num, den));
}

// LightSet::sample's points from ref follow the rule in force, tested cell by cell on the triangle (chi-square;
// cells of the map p(s, t) = p0 + s (p1 - p0) + s t (p2 - p1), planar quads): under the solid-angle rule a cell's
// probability is its solid angle over the triangle's, under the area rule its area over the triangle's. And
// LightSet::pdf, which MIS weighs a BSDF-found emitter with, is that rule's density at every sampled point.
TEST(SolidAngleSampling, PointsFollowTheRuleInForcePerTriangleShape) {
    constexpr int K = 24;
    for (const Tri& t : kTris) {
        const Scene scene = one_emitter(t);
        const LightSet lights(scene, scene.materials);
        const float omega = spherical_triangle_area(t.ref, t.p0, t.p1, t.p2);
        const dvec3 r(t.ref), p0(t.p0), p1(t.p1), p2(t.p2);
        const auto at = [&](double s, double u) { return p0 + s * (p1 - p0) + s * u * (p2 - p1); };
        const double total_omega = solid_angle_d(r, p0, p1, p2);
        const double total_area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
        std::vector<double> expected(K * K);
        for (int i = 0; i < K; ++i)
            for (int j = 0; j < K; ++j) {
                const dvec3 c00 = at(double(i) / K, double(j) / K), c10 = at(double(i + 1) / K, double(j) / K);
                const dvec3 c11 = at(double(i + 1) / K, double(j + 1) / K), c01 = at(double(i) / K, double(j + 1) / K);
                const double cell =
                    t.spherical ? (solid_angle_d(r, c00, c10, c11) + solid_angle_d(r, c00, c11, c01)) / total_omega
                                : 0.5 * glm::length(glm::cross(c11 - c00, c01 - c10)) / total_area;
                expected[size_t(i * K + j)] = cell;
            }
        const int n = 400000;
        std::vector<double> observed(K * K, 0.0);
        Pcg32 g(11, 3);
        int taken = 0, pdf_mismatch = 0;
        const dvec3 e1 = p1 - p0, e2 = p2 - p0;
        const double tri_area = total_area;
        for (int k = 0; k < n; ++k) {
            LightSample ls;
            const float pick = g.next_float();
            const float u0 = g.next_float();
            if (!lights.sample(t.ref, vec3(0.f), pick, vec2(u0, g.next_float()), ls)) continue;
            ++taken;
            // The sample's barycentrics in double, then its cell.
            const dvec3 q = dvec3(ls.p) - p0;
            const double d00 = glm::dot(e1, e1), d01 = glm::dot(e1, e2), d11 = glm::dot(e2, e2);
            const double d20 = glm::dot(q, e1), d21 = glm::dot(q, e2), den = d00 * d11 - d01 * d01;
            const double b1 = glm::clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0);
            const double b2 = glm::clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0);
            const double s = std::min(b1 + b2, 1.0), u = s > 0.0 ? b2 / s : 0.0;
            observed[size_t(std::min(int(s * K), K - 1) * K + std::min(int(u * K), K - 1))] += 1.0;
            // The pdf MIS uses at this point equals the rule's density.
            const float got = lights.pdf(0, t.ref, vec3(0.f), ls.p, ls.n);
            const double d2 = glm::dot(dvec3(ls.p) - r, dvec3(ls.p) - r);
            const double cos_l = std::fabs(glm::dot(dvec3(ls.n), glm::normalize(dvec3(ls.p) - r)));
            const double want = t.spherical ? 1.0 / double(omega) : d2 / (tri_area * cos_l);
            if (!(std::fabs(double(got) - want) <= 1e-3 * want) || !(std::fabs(got - ls.pdf) <= 1e-5f * ls.pdf))
                ++pdf_mismatch;
        }
        EXPECT_GT(taken, n * 99 / 100) << t.name;
        EXPECT_EQ(pdf_mismatch, 0) << t.name;
        // Pearson's statistic, cells expected below 5 pooled.
        double chi2 = 0.0, pool_e = 0.0, pool_o = 0.0;
        int terms = 0;
        for (size_t c = 0; c < expected.size(); ++c) {
            const double e = expected[c] * taken;
            if (e < 5.0) {
                pool_e += e;
                pool_o += observed[c];
                EXPECT_FALSE(e == 0.0 && observed[c] > 0.0) << t.name << ": a sample where none is expected";
                continue;
            }
            chi2 += (observed[c] - e) * (observed[c] - e) / e;
            ++terms;
        }
        if (pool_e >= 5.0) {
            chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
            ++terms;
        }
        ASSERT_GT(terms, 20) << t.name;
        EXPECT_GT(test::chi2_p_value(chi2, terms - 1), test::sidak_alpha(0.01, double(std::size(kTris))))
            << t.name << ": chi2 " << chi2 << " dof " << terms - 1;
    }
}

// Lambert's closed form for the irradiance a uniformly emitting polygon gives a point with normal n:
// E = L / 2 sum_i angle(v_i, v_i+1) (n . normalize(v_i x v_i+1)), the polygon wholly above the point's horizon.
double lambert_irradiance(const Tri& t, vec3 n, double le) {
    const dvec3 v[3] = {glm::normalize(dvec3(t.p0 - t.ref)), glm::normalize(dvec3(t.p1 - t.ref)),
                        glm::normalize(dvec3(t.p2 - t.ref))};
    double e = 0.0;
    for (int i = 0; i < 3; ++i) {
        const dvec3 a = v[i], b = v[(i + 1) % 3];
        e += std::acos(glm::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(dvec3(n), glm::normalize(glm::cross(a, b)));
    }
    return std::fabs(0.5 * le * e);
}

// Both rules are unbiased estimators of the irradiance (within 4 standard errors of the closed form), and near the
// emitter the solid-angle rule's variance is lower.
TEST(SolidAngleIrradiance, IrradianceMatchesLambertUnderBothRules) {
    // Receivers parallel to the emitter, facing it, so that it lies wholly above their horizon. (Not the touching
    // point: there the area rule's variance is unbounded in practice, which is why that rule is not used there.)
    for (const Tri& t : kTris) {
        if (std::string(t.name) == "touching") continue;
        const vec3 tn = glm::normalize(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
        const vec3 n = glm::dot(tn, t.ref - t.p0) > 0.f ? -tn : tn;
        const double want = lambert_irradiance(t, n, 2.0);
        const Scene scene = one_emitter(t, vec3(2.f));
        double var[2];
        for (int rule = 0; rule < 2; ++rule) {
            const LightSet lights(scene, scene.materials, rule == 0);
            Pcg32 g(7, uint64_t(rule));
            test::Moments s;
            for (int i = 0; i < 200000; ++i) {
                LightSample ls;
                const float pick = g.next_float();
                const float u0 = g.next_float();
                double x = 0.0;
                if (lights.sample(t.ref, vec3(0.f), pick, vec2(u0, g.next_float()), ls))
                    x = double(ls.le.x) * std::max(0.0, double(glm::dot(n, ls.wi))) / double(ls.pdf);
                s.add(x);
            }
            var[rule] = s.variance();
            EXPECT_NEAR(s.mean, want, 4.0 * s.stderr_of_mean() + 1e-4 * want)
                << t.name << (rule == 0 ? " (solid-angle rule)" : " (area rule)");
        }
        if (std::string(t.name) == "almost touching") {
            EXPECT_LT(var[0], 0.5 * var[1]) << t.name;
        }
    }
}

}  // namespace
}  // namespace pv
