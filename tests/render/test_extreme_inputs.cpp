// tests/render/test_extreme_inputs.cpp: inputs at the edges of the number range:
//  * grazing and extreme directions to every BSDF, the warps at the edges of the unit square, the light set at
//    degenerate reference points: finite, non-negative results or a rejected sample;
//  * NaN/Inf injection: the image stays finite and the dropped count equals the samples that hit the bad emitter;
//  * a wall at x = 0 in a box 5.5e8 wide: shadow rays are not occluded by their own wall (tnear, flush to zero).
// Test kinds: regression
#include <gtest/gtest.h>

#include "core/frame/renderer.h"
#include "core/load/obj_loader.h"
#include "core/render/lights.h"
#include "core/sampling/warp.h"
#include "core/scene/bsdf.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

// ---------------------------------------------------------------- extreme inputs

std::vector<Bsdf> all_bsdfs() {
    return {Lambertian{vec3(1.f)},
            Mirror{vec3(1.f)},
            Dielectric{1.5f},
            Dielectric{1.f / 1.5f},
            Glossy{vec3(0.f), vec3(1.f), kMinAlpha},
            Glossy{vec3(0.f), vec3(1.f), 0.2f},
            Glossy{vec3(0.f), vec3(1.f), 1.f},
            Glossy{vec3(0.5f), vec3(0.5f), 0.05f}};
}

std::vector<vec3> extreme_directions() {
    std::vector<vec3> out;
    const float cosines[] = {0.f, 1e-7f, 1e-30f, 1e-40f /* denormal */, 1.f, 0.5f};
    for (float c : cosines)
        for (float sign : {1.f, -1.f}) {
            const float z = sign * c;
            const float s = safe_sqrt(1.f - z * z);
            out.push_back(vec3(s, 0.f, z));
            out.push_back(vec3(s * 0.6f, s * 0.8f, z));
        }
    return out;
}

TEST(ExtremeInputs, BsdfsReturnFiniteNonNegativeOrReject) {
    const float us[] = {0.f, 0x1p-24f, 0.5f, kOneMinusEpsilon};
    const auto dirs = extreme_directions();
    for (const Bsdf& b : all_bsdfs())
        for (const vec3& wo : dirs) {
            for (const vec3& wi : dirs) {
                const vec3 f = eval(b, wo, wi);
                const float p = pdf(b, wo, wi);
                ASSERT_TRUE(is_finite(f) && f.x >= 0.f && f.y >= 0.f && f.z >= 0.f)
                    << bsdf_type_name(b) << " eval wo.z " << wo.z << " wi.z " << wi.z;
                ASSERT_TRUE(std::isfinite(p) && p >= 0.f) << bsdf_type_name(b) << " pdf " << p;
            }
            for (float ul : us)
                for (float u0 : us)
                    for (float u1 : us) {
                        const auto s = sample(b, wo, ul, vec2(u0, u1));
                        if (!s) continue;
                        const std::string where = std::string(bsdf_type_name(b)) + " wo.z " + std::to_string(wo.z) +
                                                  " u " + std::to_string(ul) + "," + std::to_string(u0) + "," +
                                                  std::to_string(u1);
                        ASSERT_TRUE(is_finite(s->wi)) << where;
                        ASSERT_NEAR(glm::length(s->wi), 1.f, 1e-4f) << where;
                        ASSERT_TRUE(std::isfinite(s->pdf) && s->pdf > 0.f) << where << " pdf " << s->pdf;
                        ASSERT_TRUE(is_finite(s->f) && glm::all(glm::greaterThanEqual(s->f, vec3(0.f)))) << where;
                        // The path weight stays finite (pdf never underflows to produce a huge weight).
                        const vec3 weight = s->f * std::fabs(s->wi.z) / s->pdf;
                        ASSERT_TRUE(is_finite(weight)) << where;
                        ASSERT_LE(max_component(weight) * sqr(s->eta), 1.0f + 1e-4f) << where;
                    }
        }
}

TEST(ExtremeInputs, WarpsAndHelpersAtTheEdgesOfTheUnitSquare) {
    const float us[] = {0.f, 0x1p-24f, 0.5f, kOneMinusEpsilon};
    for (float a : us)
        for (float b : us) {
            const vec2 u(a, b);
            const vec2 d = square_to_disk_concentric(u);
            EXPECT_TRUE(std::isfinite(d.x) && std::isfinite(d.y) && glm::dot(d, d) <= 1.f + 1e-6f);
            const vec3 c = square_to_cosine_hemisphere(u);
            EXPECT_TRUE(is_finite(c) && c.z >= 0.f && std::fabs(glm::length(c) - 1.f) < 1e-5f);
            EXPECT_TRUE(std::isfinite(cosine_hemisphere_pdf(c.z)));
            const vec3 s = square_to_uniform_sphere(u);
            EXPECT_TRUE(is_finite(s) && std::fabs(glm::length(s) - 1.f) < 1e-5f);
            const vec3 h = square_to_uniform_hemisphere(u);
            EXPECT_TRUE(is_finite(h) && h.z >= 0.f);
            const vec2 t = square_to_triangle(u);
            EXPECT_TRUE(t.x >= 0.f && t.y >= 0.f && t.x + t.y <= 1.f + 1e-6f);
            for (const vec3& wo : extreme_directions()) {
                if (wo.z <= 0.f) continue;
                for (float alpha : {kMinAlpha, 0.2f, 1.f}) {
                    const vec3 m = ggx_sample_visible_normal(wo, alpha, u);
                    EXPECT_TRUE(is_finite(m) && m.z > 0.f) << "wo.z " << wo.z << " alpha " << alpha;
                    EXPECT_TRUE(std::isfinite(ggx_d(m, alpha)) && ggx_d(m, alpha) >= 0.f);
                    EXPECT_TRUE(std::isfinite(ggx_g1(wo, alpha)) && ggx_g1(wo, alpha) >= 0.f &&
                                ggx_g1(wo, alpha) <= 1.f);
                }
            }
        }
    for (float c : {0.f, 1e-7f, -1e-7f, 1e-30f, 1e-40f, 1.f, -1.f, 2.f, -2.f}) {
        const float r = fresnel_dielectric(c, 1.5f);
        EXPECT_TRUE(r >= 0.f && r <= 1.f) << "cos " << c;
    }
}

TEST(ExtremeInputs, LightSetAtDegenerateReferencePoints) {
    Scene scene;
    Material m;
    m.emission = vec3(3.f);
    scene.materials.push_back(m);
    test::add_quad(scene, vec3(0, 1, 0), vec3(1, 1, 0), vec3(1, 1, 1), vec3(0, 1, 1), 0);
    LightSet lights(scene, scene.materials);
    const float us[] = {0.f, 0x1p-24f, 0.5f, kOneMinusEpsilon};
    // On the light's plane (cos 0), on a vertex and on an edge (distance 0), far away, and a regular point; with
    // no receiver normal and with one (the light tree weighs it).
    const vec3 refs[] = {
        vec3(2, 1, 0.5f),        vec3(0, 1, 0), vec3(0.5f, 1, 0), vec3(0.5f, 0.f, 0.5f), vec3(0.5f, 1e-30f + 1.f, 0.5f),
        vec3(1e30f, -1e30f, 0.f)};
    for (const LightSamplerKind kind : {LightSamplerKind::Power, LightSamplerKind::Tree}) {
        lights.set_sampler(kind);
        for (const vec3& ref : refs)
            for (const vec3& n : {vec3(0.f), vec3(0.f, 1.f, 0.f)})
                for (float a : us)
                    for (float b : us)
                        for (float c : us) {
                            LightSample s;
                            if (!lights.sample(ref, n, a, vec2(b, c), s)) continue;
                            EXPECT_TRUE(std::isfinite(s.pdf) && s.pdf > 0.f);
                            EXPECT_TRUE(is_finite(s.wi) && is_finite(s.le) && is_finite(s.p));
                            EXPECT_TRUE(s.dist > 0.f && std::isfinite(s.dist));
                        }
    }
}

// ---------------------------------------------------------------- NaN / Inf injection

// A test-only material whose emission is NaN (and one +Inf) on small triangles in front of a lit plane. The
// light set ignores them (their power is not a positive number); a camera sample that hits one's front face
// carries NaN/Inf and must be dropped and counted, never accumulated. Paths from the plane see only their back
// faces (one-sided emission), so the dropped count equals the camera samples hitting the fronts, counted by
// tracing the same camera rays (the Renderer's sample layout: jitter, then lens).
TEST(NanInjection, DroppedCountEqualsCameraSamplesOnTheBadEmitter) {
    auto scene = std::make_shared<Scene>();
    Material plane, nan_mat, inf_mat, light;
    plane.bsdf = Lambertian{vec3(0.5f)};
    nan_mat.emission = vec3(std::numeric_limits<float>::quiet_NaN());
    inf_mat.emission = vec3(std::numeric_limits<float>::infinity(), 1.f, 1.f);
    light.emission = vec3(4.f);
    const uint32_t mp = test::add_material(*scene, plane), mn = test::add_material(*scene, nan_mat),
                   mi = test::add_material(*scene, inf_mat), ml = test::add_material(*scene, light);
    test::add_quad(*scene, vec3(-3, -3, -1), vec3(3, -3, -1), vec3(3, 3, -1), vec3(-3, 3, -1), mp);
    scene->add_triangle(vec3(-0.3f, -0.2f, 0), vec3(0.1f, -0.2f, 0), vec3(-0.1f, 0.25f, 0), mn);  // faces +z
    scene->add_triangle(vec3(0.4f, 0.3f, 0), vec3(0.6f, 0.3f, 0), vec3(0.5f, 0.5f, 0), mi);
    test::add_quad(*scene, vec3(-1, 2, -0.5f), vec3(-1, 2, 0.5f), vec3(1, 2, 0.5f), vec3(1, 2, -0.5f), ml);
    scene->environment.background = vec3(0.2f);
    CameraDesc cam;
    cam.eye = vec3(0.f, 0.f, 3.f);
    cam.target = vec3(0.f);
    cam.vfov_deg = 40.f;
    const int w = 24, h = 24, spp = 16;
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    s.seed = 77;
    Renderer r(scene, 2);
    r.restart(cam, s, w, h);
    for (int i = 0; i < spp; ++i) r.render_pass();
    // Count camera samples hitting the bad triangles' front faces.
    const Accel accel(*scene);
    const Camera camera(cam, w, h);
    uint64_t expected = 0;
    for (int i = 0; i < spp; ++i)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                Sampler sampler(s.seed, s.sampler);  // as the Renderer draws camera samples
                const Ray ray = camera_ray(camera, sampler, x, y, uint32_t(i));
                Hit hit;
                if (accel.intersect(ray, hit) && (hit.prim == 2 || hit.prim == 3)) ++expected;
            }
    EXPECT_GT(expected, 10u);
    EXPECT_EQ(r.stats().dropped, expected);
    test::expect_finite_and_lit(r.film().mean());
    EXPECT_EQ(r.traceable().triangle_lights().pmf(2), 0.f);
    EXPECT_EQ(r.traceable().triangle_lights().pmf(3), 0.f);
}

// A wall in the plane x = 0 of a box 5.5e8 wide (the Cornell box scaled by 1e6): every vertex has x = 0 exactly,
// so hit points have x = 0 and a zero error bound, and the spawned origin sits a hair off the wall. A shadow ray
// from there to a point 2.4e8 away has a hit distance on its own wall of about -4e-39, which FTZ flushes to -0;
// with tnear = 0 Embree counted that as a hit and about half of such shadow rays were occluded by their own wall
// (measured: 104691 of 244624 shadow rays in the scaled Cornell box, against 47792 truly occluded). Accel's
// tnear = FLT_MIN rejects it. Breaks with: tnear = 0 in core/render/accel.cpp.
TEST(ZeroCoordinateWall, ShadowRaysAreNotOccludedByTheirOwnWallAtHugeScale) {
    const ScopedFtzDaz ftz;  // trace as the renderer's threads do, with flush-to-zero and denormals-are-zero
    for (float scale : {1.f, 1e6f, 1e8f}) {
        Scene scene;
        const uint32_t m = test::add_material(scene, Material{});
        const float w = 555.f * scale;
        test::add_quad(scene, vec3(0, 0, 0), vec3(0, 0, w), vec3(0, w, w), vec3(0, w, 0), m);
        const Accel accel(scene);
        Pcg32 g(7, 3);
        int occluded = 0, spawned = 0;
        for (int i = 0; i < 2000; ++i) {
            // A point on the wall, reached from inside the box, and a target inside the box.
            const vec3 on_wall(0.f, w * (0.05f + 0.9f * g.next_float()), w * (0.05f + 0.9f * g.next_float()));
            Ray r;
            r.o = on_wall + vec3(0.5f * w, 0.f, 0.f);
            r.d = vec3(-1.f, 0.f, 0.f);
            Hit h;
            if (!accel.intersect(r, h)) continue;
            const SurfacePoint sp = surface_point(scene, h);
            const vec3 n = sp.ng.x > 0.f ? sp.ng : -sp.ng;  // toward the inside (+x)
            const vec3 target(w * (0.1f + 0.8f * g.next_float()), w * g.next_float(), w * g.next_float());
            Ray shadow;
            shadow.o = offset_ray_origin(sp.p, n, sp.p_error);
            shadow.d = target - shadow.o;
            shadow.tmax = 1.f - 1e-4f;
            ++spawned;
            occluded += accel.occluded(shadow) ? 1 : 0;
        }
        EXPECT_GT(spawned, 1900) << "scale " << scale;
        EXPECT_EQ(occluded, 0) << "scale " << scale << ": shadow rays occluded by their own wall";
    }
}

}  // namespace
}  // namespace pv
