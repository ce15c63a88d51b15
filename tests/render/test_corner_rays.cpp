// tests/render/test_corner_rays.cpp: rays in a concave corner (a 90 or 5 degree wedge, from 1e-3 to 1e3 units):
//  * rays spawned (as the integrator spawns them) from one face toward the other at grazing angles hit the other
//    face at the analytic t; none re-hits its own face or leaks through the other;
//  * contact shadow: direct light from a uniform sky on the wedge has a closed form (1 minus Lambert's polygon form
//    factor of the other face); the rendered corner matches it per sample point, within Sidak-corrected bounds
//    from the sample variance (alpha = 0.01).
// Test kinds: regression
#include <gtest/gtest.h>

#include <cmath>

#include "core/render/accel.h"
#include "core/render/surface.h"
#include "core/sampling/rng.h"
#include "core/sampling/warp.h"
#include "tests/support/quads.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

using test::face_of;
using test::kPiD;

// ---------------------------------------------------------------- concave corner

// Two quads sharing the z axis as an edge: face 0 in the plane y = 0 (x in [0, s]), face 1 rotated about z by the
// dihedral angle theta; both of half-width s in z. e[i] points away from the edge within face i, n[i] is face i's
// normal facing into the wedge. Triangles 0, 1 are face 0; 2, 3 are face 1.
struct Corner {
    double theta = 0.0;
    float scale = 1.f;
    vec3 e[2], n[2];
};

Corner make_corner(double theta_deg, float scale) {
    Corner c;
    c.theta = theta_deg * kPiD / 180.0;
    c.scale = scale;
    c.e[0] = vec3(1.f, 0.f, 0.f);
    c.n[0] = vec3(0.f, 1.f, 0.f);
    c.e[1] = vec3(float(std::cos(c.theta)), float(std::sin(c.theta)), 0.f);
    c.n[1] = vec3(float(std::sin(c.theta)), float(-std::cos(c.theta)), 0.f);
    return c;
}

void add_corner(Scene& scene, const Corner& c, uint32_t material) {
    const vec3 z(0.f, 0.f, c.scale);
    for (int i = 0; i < 2; ++i) {
        const vec3 far = c.scale * c.e[i];
        vec3 q[4] = {-z, z, far + z, far - z};
        if (glm::dot(glm::cross(q[1] - q[0], q[2] - q[0]), c.n[i]) < 0.f) std::swap(q[1], q[3]);
        test::add_quad(scene, q[0], q[1], q[2], q[3], material);
    }
}

// The point x0 e[face] + z0 z of a corner, reached by a ray from inside the wedge (so that p and its error bound
// come from Embree's barycentrics, as in the integrator). False if that ray does not land on `face`.
bool corner_point(const Scene& scene, const Accel& accel, const Corner& c, int face, float x0, float z0,
                  SurfacePoint& out) {
    const vec3 target = x0 * c.e[face] + vec3(0.f, 0.f, z0);
    const vec3 eye = target + 0.5f * x0 * float(std::tan(c.theta / 2)) * c.n[face];
    Ray r;
    r.o = eye;
    r.d = glm::normalize(target - eye);
    Hit h;
    if (!accel.intersect(r, h) || face_of(h.prim) != face) return false;
    out = surface_point(scene, h);
    return true;
}

struct CornerRayStats {
    int tested = 0, skipped = 0;
    int misses = 0, own_face = 0, leaks = 0, bad_t = 0;
    double worst_rel_t = 0.0;
    std::string first_failure;
    int failures() const { return misses + own_face + leaks + bad_t; }
};

// `rays` rays from face `from` toward the other face. The start point is reached by a ray from inside the wedge
// (so p and its error bound come from Embree's barycentrics); the direction makes an angle delta = 10^U(-3, -0.5)
// radians with face `from` (grazing it) or with the other face (grazing that), or is uniform over the directions
// that reach it, and leans out of the cross-section by up to 0.6 rad. The expected t is the ray's intersection with
// the other face's plane in double (from the float origin, direction and vertices); rays whose predicted hit lies
// beyond the finite face are skipped (that is the choice of direction, not a robustness question).
CornerRayStats trace_corner_rays(const Corner& c, int from, int rays, uint64_t seed) {
    const ScopedFtzDaz ftz;  // the renderer's floating-point mode
    Scene scene;
    add_corner(scene, c, test::add_material(scene, Material{}));
    const Accel accel(scene);
    const int to = 1 - from;
    const uvec3 tt = scene.triangles[size_t(2 * to)];
    const dvec3 q0(scene.positions[tt.x]);
    dvec3 nt = glm::normalize(glm::cross(dvec3(scene.positions[tt.y]) - q0, dvec3(scene.positions[tt.z]) - q0));
    if (glm::dot(nt, dvec3(c.n[to])) < 0.0) nt = -nt;
    const double s = c.scale;
    Pcg32 g(seed, 11);
    CornerRayStats st;
    auto fail = [&](int& counter, const std::string& what) {
        if (++counter, st.failures() == 1) st.first_failure = what;
    };
    for (int i = 0; i < rays; ++i) {
        // Start point x0 e + z0 z with x0 = s 10^U(-3, 0) (dense near the edge).
        const float x0 = float(s * std::pow(10.0, -3.0 * g.next_float()));
        const float z0 = float(s * (g.next_float() - 0.5));
        SurfacePoint sp;
        if (!corner_point(scene, accel, c, from, x0, z0, sp)) {
            ++st.skipped;
            continue;
        }
        // Direction at angle phi from e[from] in the cross-section (phi in (theta, pi) reaches the other face).
        const double delta = std::pow(10.0, -3.0 + 2.5 * g.next_float());
        const float mode = g.next_float();
        const double phi = mode < 1.f / 3   ? kPiD - delta
                           : mode < 2.f / 3 ? c.theta + delta
                                            : c.theta + (kPiD - c.theta) * g.next_float();
        const double beta = 0.6 * (2.0 * g.next_float() - 1.0);
        const dvec3 dd = std::cos(beta) * (std::cos(phi) * dvec3(c.e[from]) + std::sin(phi) * dvec3(c.n[from])) +
                         std::sin(beta) * dvec3(0, 0, 1);
        Ray r;
        r.d = glm::normalize(vec3(dd));
        r.o = offset_ray_origin(sp.p, glm::dot(r.d, sp.ng) > 0.f ? sp.ng : -sp.ng, sp.p_error);
        const dvec3 o(r.o), d(r.d);
        const double side = glm::dot(nt, o - q0), denom = glm::dot(nt, d);
        const double t_ref = -side / denom;
        const dvec3 at = o + t_ref * d;
        const double r_at = glm::dot(at, dvec3(c.e[to]));
        const bool on_face = r_at < s && std::fabs(at.z) < s;
        if (side <= 0.0) {
            // The offset origin is not inside the wedge: the ray starts behind the other face (a light leak).
            fail(st.leaks, "origin behind the other face at x0 = " + std::to_string(x0 / s) + " s");
            ++st.tested;
            continue;
        }
        if (!on_face || !(denom < 0.0)) {
            ++st.skipped;
            continue;
        }
        ++st.tested;
        Hit h;
        if (!accel.intersect(r, h)) {
            fail(st.misses, "miss, t_ref " + std::to_string(t_ref / s) + " s");
            continue;
        }
        if (face_of(h.prim) == from) {
            fail(st.own_face, "own face re-hit at t " + std::to_string(h.t / s) + " s, x0 " + std::to_string(x0 / s));
            continue;
        }
        const double rel = std::fabs(double(h.t) - t_ref) / t_ref;
        st.worst_rel_t = std::max(st.worst_rel_t, rel);
        if (rel >= 1e-3) fail(st.bad_t, "t " + std::to_string(h.t) + " vs " + std::to_string(t_ref));
    }
    return st;
}

void expect_corner_rays_clean(double angle, float scale) {
    for (int from : {0, 1}) {
        const Corner c = make_corner(angle, scale);
        const uint64_t seed = uint64_t(angle) * 100 + uint64_t(std::log10(scale) + 3) * 2 + uint64_t(from);
        const CornerRayStats st = trace_corner_rays(c, from, 10000, seed);
        SCOPED_TRACE(testing::Message() << angle << " degrees, scale " << scale << ", from face " << from);
        EXPECT_GT(st.tested, 7000) << "skipped " << st.skipped;
        EXPECT_EQ(st.failures(), 0) << "misses " << st.misses << ", own-face hits " << st.own_face << ", leaks "
                                    << st.leaks << ", bad t " << st.bad_t << " of " << st.tested
                                    << "; first: " << st.first_failure;
        EXPECT_LT(st.worst_rel_t, 1e-3);
    }
}

// Breaks if the offset no longer clears the spawning face (own-face hits), pushes the origin through the other
// face (leaks), or if p or t drift (e.g. p taken as o + t d, or a non-robust triangle test at grazing angles).
TEST(CornerRays, RightAngleGrazingRaysHitTheOtherFaceAtTheAnalyticT) {
    for (float scale : {1e-3f, 1.f, 1e3f}) expect_corner_rays_clean(90.0, scale);
}
TEST(CornerRays, FiveDegreeGrazingRaysHitTheOtherFaceAtTheAnalyticT) {
    for (float scale : {1.f, 1e3f}) expect_corner_rays_clean(5.0, scale);
}
// A millimetre-sized 5 degree wedge: Waechter and Binder's near-origin branch (move |p| < 1/32 by an absolute
// 1/65536) is not scale-invariant: 1.5e-5 units is 1.5% of this 1e-3 wedge, more than the gap x0 tan(5 deg) to
// the other face for x0 < 0.17 s, and ~75% of these rays started behind the other face until offset_ray_origin
// kept that branch for |p| < 1e-30 only (core/base/math.h).
TEST(CornerRays, FiveDegreeMillimetreScaleDoesNotLeak) { expect_corner_rays_clean(5.0, 1e-3f); }

// ---------------------------------------------------------------- contact shadow in a corner

// Lambert's formula: the form factor from a differential area at p with unit normal n to the polygon v (seen from
// its front or back), (1 / 2 pi) |sum_i angle(a_i, a_i+1) n . unit(a_i x a_i+1)|, a_i = unit(v_i - p)
// (e.g. Arvo 1995, "Analytic methods for simulated light transport", eq. 3.5). Exact for any p off the polygon.
double polygon_form_factor(dvec3 p, dvec3 n, const dvec3* v, int count) {
    double sum = 0.0;
    for (int i = 0; i < count; ++i) {
        const dvec3 a = glm::normalize(v[i] - p), b = glm::normalize(v[(i + 1) % count] - p);
        const dvec3 c = glm::cross(a, b);
        const double len = glm::length(c);
        if (len == 0.0) continue;
        sum += std::atan2(len, glm::dot(a, b)) * glm::dot(n, c / len);
    }
    return std::fabs(sum) / (2.0 * kPiD);
}

// The wedge under a uniform sky L_env with Lambertian faces of albedo rho, direct light only (max_depth 1): a
// point p on one face sees the sky except where the other face blocks it (the other face is black at depth 1, and
// its own face lies in p's tangent plane), so L(p) = rho L_env (1 - F(p -> other face)) exactly, for every p,
// including the contact region next to the edge. Each sample takes a fresh point (x0 = s 10^U(-3, 0), so half the
// points lie within 3% of the edge) and one path, so the differences D = L_sample - L(p) are i.i.d. with mean 0
// for an unbiased renderer; |mean(D)| <= k stderr(D), with k Sidak-corrected over the family (2 angles x scales
// x 2 estimators x 2 faces x 3 decades of x0). Per decade, so that a leak or an over-shadowing confined to the
// contact region is not averaged away.
// Breaks with: a leak (origin behind the other face: too bright), self-shadowing of the shadow ray or the
// continuation (too dark), a shadow-ray tmax that stops short of / runs past the sky, MIS weights that do not sum
// to one. Measured: the 5 degree wedge at scale 1e-3 (the leak of FiveDegreeMillimetreScaleDoesNotLeak)
// fails every bin, |z| = 50 to 2800; the enabled cases pass with max |z| ~ 2.5 against k = 3.8.
struct ShadowCase {
    double angle;
    float scale;
};

int expect_corner_direct_light(const ShadowCase& sc, bool nee, int samples, double family) {
    const ScopedFtzDaz ftz;  // the renderer's floating-point mode
    const Corner c = make_corner(sc.angle, sc.scale);
    const double rho = 0.8, l_env = 1.0;
    auto scene = std::make_shared<Scene>();
    Material m;
    m.bsdf = Lambertian{vec3(float(rho))};
    add_corner(*scene, c, test::add_material(*scene, m));
    scene->environment.background = vec3(float(l_env));
    const test::Tracer tracer(scene);
    dvec3 quad[2][4];
    for (int f = 0; f < 2; ++f) {
        const uvec3 t0 = scene->triangles[size_t(2 * f)], t1 = scene->triangles[size_t(2 * f + 1)];
        quad[f][0] = dvec3(scene->positions[t0.x]);
        quad[f][1] = dvec3(scene->positions[t0.y]);
        quad[f][2] = dvec3(scene->positions[t0.z]);
        quad[f][3] = dvec3(scene->positions[t1.z]);
    }
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    s.light_sampling = nee;
    s.mis = nee;
    s.russian_roulette = false;
    s.max_depth = 1;
    s.seed = uint32_t(sc.angle) * 10 + uint32_t(std::log10(sc.scale) + 3) * 2 + (nee ? 1 : 0);
    Sampler sampler(s.seed, s.sampler);
    PathCounters counters;
    Pcg32 g(s.seed, 5);
    test::Moments diff[2][3], value[2][3];
    int checks = 0;
    for (int i = 0; i < samples; ++i) {
        const int face = int(g.next_u32() & 1u);
        const float u = g.next_float();
        const int decade = std::min(2, int(3.f * u));
        const float x0 = float(sc.scale * std::pow(10.0, -3.0 * u));
        const float z0 = float(sc.scale * (g.next_float() - 0.5));
        const vec3 target = x0 * c.e[face] + vec3(0.f, 0.f, z0);
        Ray r;
        r.o = target + 0.5f * x0 * float(std::tan(c.theta / 2)) * c.n[face];
        r.d = glm::normalize(target - r.o);
        Hit h;
        if (!tracer.accel().intersect(r, h) || face_of(h.prim) != face) continue;
        const SurfacePoint sp = surface_point(*scene, h);
        const double expected =
            rho * l_env * (1.0 - polygon_form_factor(dvec3(sp.p), dvec3(c.n[face]), quad[1 - face], 4));
        sampler.start(uvec2(uint32_t(i % 4096), uint32_t(i / 4096)), 0);
        sampler.reserve(kCameraDims);
        const vec3 v = trace_path(tracer, s, r, sampler, counters);
        diff[face][decade].add(double(v.x) - expected);
        value[face][decade].add(expected);
    }
    const double k = test::sidak_k(family);
    for (int f = 0; f < 2; ++f)
        for (int d = 0; d < 3; ++d) {
            const test::Moments& m2 = diff[f][d];
            ++checks;
            EXPECT_GT(m2.n, uint64_t(samples / 10));
            const double se = m2.stderr_of_mean();
            EXPECT_LE(std::fabs(m2.mean), k * se + 1e-6 * value[f][d].mean)
                << sc.angle << " deg, scale " << sc.scale << (nee ? ", NEE+MIS" : ", BSDF only") << ", face " << f
                << ", x0 / s in [1e-" << d + 1 << ", 1e-" << d << "]: mean L - expected " << m2.mean << ", stderr "
                << se << ", expected " << value[f][d].mean << ", k " << k;
        }
    return checks;
}

const ShadowCase kShadowCases[] = {{90.0, 1e-3f}, {90.0, 1.f}, {90.0, 1e3f}, {5.0, 1.f}, {5.0, 1e3f}};

TEST(CornerContactShadow, DirectSkyLightMatchesLambertFormFactor) {
    const double family = double(std::size(kShadowCases)) * 2 * 6;
    for (const ShadowCase& sc : kShadowCases)
        for (bool nee : {false, true}) expect_corner_direct_light(sc, nee, 60000, family);
}
// The leak FiveDegreeMillimetreScaleDoesNotLeak guards against, as it would show in the image: too bright next
// to the edge.
TEST(CornerContactShadow, FiveDegreeMillimetreScale) {
    for (bool nee : {false, true}) expect_corner_direct_light({5.0, 1e-3f}, nee, 60000, 2 * 6);
}

}  // namespace
}  // namespace pv
