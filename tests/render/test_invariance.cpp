// tests/render/test_hard.cpp: hard numerical cases (self-intersection, degenerate triangles, grazing angles, shading
// normals, NaN guards, float accumulation):
//  * scale and translation invariance of the Cornell box;
//  * grazing and extreme inputs to every BSDF, warp and the light set;
//  * shading normals: zero, flipped, a low-poly smooth sphere in the furnace, Veach's same-side rule;
//  * degenerate, sliver and huge triangles; a zero-area emitter is never sampled;
//  * NaN/Inf injection: the image stays finite and the dropped count equals the samples that hit the bad emitter;
//  * long accumulation in the film.
#include <gtest/gtest.h>

#include <chrono>

#include "core/frame/renderer.h"
#include "core/load/obj_loader.h"
#include "core/render/lights.h"
#include "core/sampling/warp.h"
#include "core/scene/bsdf.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

// ---------------------------------------------------------------- scale and translation invariance

std::shared_ptr<Scene> transformed_cornell(float scale, vec3 translate) {
    auto s = std::make_shared<Scene>(*test::cornell_box());
    for (vec3& p : s->positions) p = p * scale + translate;
    s->camera.eye = s->camera.eye * scale + translate;
    s->camera.target = s->camera.target * scale + translate;
    return s;
}

// Statistically identical images (per-pixel Welch + total mean, independent seeds) for the Cornell box scaled by s
// or translated by T along (1, 0.6, -0.8) (camera included). The asserted range is the issue's (s = 1e-4..1e4,
// T up to 1e5). Measured beyond it with the same 16x16, 128 spp comparison (with the scale-free near-origin offset
// and tnear = FLT_MIN): s = 1e-8 .. 1e7 and T = 3e5 .. 1e6 pass; T = 1e7 fails (63 of 768 pixel-channels) at the
// box's edges and corners (a float ULP at 1e7 is 1 unit and the 256-ULP offset 256 units of a 556-unit box), and
// s = 1e8 fails everywhere (210).
TEST(Invariance, CornellBoxUnderScaleAndTranslation) {
    RenderSettings base;
    base.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    base.seed = 500;
    auto scene = test::cornell_box();
    const int w = 16, h = 16, spp = 128;
    const auto ref = test::PixelStats::from_film(test::render_with_renderer(scene, scene->camera, base, w, h, spp));
    struct Variant {
        float s;
        float t;
    };
    const Variant variants[] = {{1e-4f, 0}, {1e-2f, 0}, {1e2f, 0}, {1e4f, 0},
                                {1, 1e2f},  {1, 1e3f},  {1, 1e4f}, {1, 1e5f}};
    uint32_t seed = 501;
    for (const Variant& v : variants) {
        auto s = transformed_cornell(v.s, v.t * vec3(1.f, 0.6f, -0.8f));
        RenderSettings rs = base;
        rs.seed = seed++;
        const auto img = test::PixelStats::from_film(test::render_with_renderer(s, s->camera, rs, w, h, spp));
        const auto c = test::compare_images(ref, img);
        EXPECT_TRUE(c.passed) << "scale " << v.s << ", translation " << v.t << ": " << c.describe();
    }
}

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

// ---------------------------------------------------------------- shading normals

const char* kNormalsObj = R"(# a floor quad and a ceiling light quad facing down
v -1 0 -1
v 1 0 -1
v 1 0 1
v -1 0 1
v -0.3 1 -0.3
v 0.3 1 -0.3
v 0.3 1 0.3
v -0.3 1 0.3
vn 0 0 0
vn 0 1 0
vn 0 -1 0
)";

Scene normals_scene(const std::string& floor_normal_ref) {
    std::string text = kNormalsObj;
    text += "f 1" + floor_normal_ref + " 4" + floor_normal_ref + " 3" + floor_normal_ref + "\n";
    text += "f 1" + floor_normal_ref + " 3" + floor_normal_ref + " 2" + floor_normal_ref + "\n";
    text += "f 5 6 7\nf 5 7 8\n";
    Scene s = load_obj_from_string(text, "normals.obj");
    s.materials.back().emission = vec3(0.f);
    Material light;
    light.emission = vec3(5.f);
    s.materials.push_back(light);
    s.material_ids[2] = s.material_ids[3] = uint32_t(s.materials.size() - 1);
    s.camera.eye = vec3(0.f, 0.5f, 2.5f);
    s.camera.target = vec3(0.f, 0.2f, 0.f);
    return s;
}

// Zero normals fall back to the geometric normal, and normals opposite to the winding are flipped to its side:
// both render bit-identical to the same scene without normals.
TEST(ShadingNormals, ZeroAndFlippedNormalsRenderLikeNoNormals) {
    const Scene none = normals_scene(""), zero = normals_scene("//1"), flipped = normals_scene("//3"),
                right = normals_scene("//2");
    // Corners without a usable normal, counted per triangle: the light's 2 (none given) and the floor's 2 (zero).
    EXPECT_EQ(zero.stats.bad_normals, 4u);
    EXPECT_EQ(right.stats.bad_normals, 2u);
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    s.seed = 3;
    auto film_of = [&](const Scene& sc) {
        auto p = std::make_shared<Scene>(sc);
        return test::render_with_renderer(p, p->camera, s, 12, 12, 8);
    };
    const Film a = film_of(none), b = film_of(zero), c = film_of(flipped), d = film_of(right);
    double total = 0.0;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x)
            for (int ch = 0; ch < 3; ++ch) {
                const double va = a.pixel(x, y).sum[ch];
                EXPECT_EQ(va, b.pixel(x, y).sum[ch]) << "zero normals at " << x << "," << y;
                EXPECT_EQ(va, c.pixel(x, y).sum[ch]) << "flipped normals at " << x << "," << y;
                EXPECT_EQ(va, d.pixel(x, y).sum[ch]) << "correct normals at " << x << "," << y;
                total += va;
            }
    EXPECT_GT(total, 0.0);
}

// A low-poly (8 x 6) smooth-shaded sphere of albedo 1 in a white furnace: shading normals disagree with the
// facets, so some paths are cut (the same-side rule), but no sample may exceed L (no energy gain), none is NaN,
// and no pixel on the sphere is black.
TEST(ShadingNormals, LowPolySmoothSphereInFurnace) {
    auto scene = std::make_shared<Scene>();
    Material m;
    m.bsdf = Lambertian{vec3(1.f)};
    test::add_uv_sphere(*scene, vec3(0.f), 1.f, 8, 6, test::add_material(*scene, m), /*smooth=*/true);
    ASSERT_FALSE(scene->normal_indices.empty());
    scene->environment.background = vec3(1.f);
    const test::Tracer tracer(scene);
    CameraDesc cam;
    cam.eye = vec3(0.2f, 0.5f, 3.f);
    cam.target = vec3(0.f);
    cam.vfov_deg = 45.f;
    for (bool rr : {false, true}) {
        RenderSettings s;
        s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
        s.russian_roulette = rr;
        // Without roulette: BSDF sampling only, so each sample is exactly 1 or 0. With roulette: light sampling
        // of the (constant) environment too, so only the mean is bounded.
        s.light_sampling = rr;
        s.seed = rr ? 8 : 9;
        size_t above = 0, nan = 0;
        vec3 first_above(0.f);
        Film film(16, 16);
        tracer.for_each_sample(cam, s, 16, 16, 32, [&](int x, int y, uint32_t i, vec3 v) {
            if (!is_finite(v)) ++nan;
            // Without roulette every weight is f cos / pdf = 1, so a sample is 1 (escaped) or 0 (cut);
            // with roulette a survivor carries 1 / q, so only the mean is bounded (below).
            if (!rr && max_component(v) > 1.f + 1e-5f && ++above == 1) first_above = v;
            film.add(x, y, i, v);
        });
        EXPECT_EQ(nan, 0u);
        EXPECT_EQ(above, 0u) << "samples above L: energy gain, first " << first_above.x;
        const auto st = test::PixelStats::from_film(film);
        const double k = test::sidak_k(16.0 * 16 * 2);
        for (size_t i = 0; i < st.mean.size(); i += 3) {
            EXPECT_LE(st.mean[i], 1.0 + k * std::sqrt(st.var_mean[i]) + 1e-5) << "pixel " << i / 3;
            EXPECT_GT(st.mean[i], 0.0) << "black pixel " << i / 3;
        }
    }
}

// Veach's rule: where wo is on the front of the geometric normal but the back of the shading normal, the
// integrator shades with the geometric normal, so such a ray gives exactly the flat-shaded result.
TEST(ShadingNormals, SameSideRuleFallsBackToGeometricNormal) {
    auto make = [](bool tilted) {
        auto s = std::make_shared<Scene>();
        Material floor, light;
        light.emission = vec3(2.f);
        light.bsdf = Lambertian{vec3(0.f)};
        const uint32_t mf = test::add_material(*s, floor), ml = test::add_material(*s, light);
        test::add_quad(*s, vec3(-1, 0, -1), vec3(-1, 0, 1), vec3(1, 0, 1), vec3(1, 0, -1), mf);  // normal +y
        test::add_quad(*s, vec3(-1, 2, -1), vec3(1, 2, -1), vec3(1, 2, 1), vec3(-1, 2, 1), ml);  // facing down
        s->environment.background = vec3(0.3f);
        if (tilted) {
            // Shading normals leaning hard towards +x on the floor.
            s->normals = {glm::normalize(vec3(1.f, 0.15f, 0.f))};
            s->normal_indices.assign(s->triangles.size(), uvec3(kNoIndex));
            s->normal_indices[0] = s->normal_indices[1] = uvec3(0);
        }
        return s;
    };
    const test::Tracer flat(make(false)), tilted(make(true));
    CameraDesc cam;
    cam.eye = vec3(-3.f, 0.4f, 0.f);  // looking along +x at a grazing angle: wo has negative x
    cam.target = vec3(0.f, 0.f, 0.f);
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    s.seed = 4;
    std::vector<vec3> a, b;
    flat.for_each_sample(cam, s, 8, 8, 4, [&](int, int, uint32_t, vec3 v) { a.push_back(v); });
    tilted.for_each_sample(cam, s, 8, 8, 4, [&](int, int, uint32_t, vec3 v) { b.push_back(v); });
    ASSERT_EQ(a.size(), b.size());
    // Floor pixels seen from this side have wo . ns < 0 < wo . ng: the rule applies to the first hit; later
    // bounces may see the shading normal, so only first-hit-dominated equality can be asserted: with max_depth 1.
    s.max_depth = 1;
    a.clear();
    b.clear();
    flat.for_each_sample(cam, s, 8, 8, 4, [&](int, int, uint32_t, vec3 v) { a.push_back(v); });
    tilted.for_each_sample(cam, s, 8, 8, 4, [&](int, int, uint32_t, vec3 v) { b.push_back(v); });
    int floor_samples = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i], b[i]) << "sample " << i;
        floor_samples += a[i] != vec3(0.3f);
    }
    EXPECT_GT(floor_samples, 0);
}

// ---------------------------------------------------------------- degenerate geometry

TEST(DegenerateGeometry, LoaderDropsAndCountsAndRenderStaysFinite) {
    const std::string obj = R"(v 0 0 0
v 1 0 0
v 2 0 0
v 0 1 0
v 1e-7 0 0
v 0 0 1
v 1e19 0 0
v 0 1e18 0
v 1 1e18 0
v 1 -1 0
f 1 2 3
f 1 1 4
f 1 5 4
f 1 4 6
f 1 7 4
f 2 8 9
f 1 2 10
)";
    // 1 2 3 collinear and 1 1 4 coincident: zero area. 1 5 4: sliver (aspect 1e7), kept. 1 4 6: fine.
    // 1 7 4: a vertex beyond 1.844e18, dropped as non-finite. 2 8 9: at 1e18, kept or dropped, never NaN.
    const Scene s = load_obj_from_string(obj, "degenerate.obj");
    EXPECT_EQ(s.stats.dropped_degenerate + s.stats.dropped_nonfinite + s.triangles.size(), 7u);
    EXPECT_GE(s.stats.dropped_degenerate, 2u);
    EXPECT_EQ(s.stats.dropped_nonfinite, 1u);
    EXPECT_GE(s.triangles.size(), 3u);
    bool warned = false;
    for (const std::string& w : s.warnings) warned |= w.find("zero-area") != std::string::npos;
    EXPECT_TRUE(warned);
    auto scene = std::make_shared<Scene>(s);
    scene->environment.background = vec3(1.f);
    CameraDesc cam;
    cam.eye = vec3(0.5f, 0.3f, 3.f);
    cam.target = vec3(0.3f, 0.3f, 0.f);
    uint64_t dropped = 0;
    const Film film = test::render_with_renderer(scene, cam, RenderSettings{}, 16, 16, 8, 2, &dropped);
    EXPECT_EQ(dropped, 0u);
    const Image img = film.mean();
    for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v));
}

TEST(DegenerateGeometry, ZeroAreaEmitterIsNeverSampled) {
    Scene scene;
    Material light;
    light.emission = vec3(10.f);
    scene.materials.push_back(light);
    scene.add_triangle(vec3(0, 1, 0), vec3(1, 1, 0), vec3(2, 1, 0), 0);  // collinear
    scene.add_triangle(vec3(3, 1, 3), vec3(3, 1, 3), vec3(3, 2, 3), 0);  // coincident vertices
    scene.add_triangle(vec3(0, 2, 0), vec3(0, 2, 1), vec3(1, 2, 0), 0);  // a real light, facing down
    const LightSet lights(scene, scene.materials);
    EXPECT_EQ(lights.size(), 1u);
    EXPECT_EQ(lights.pmf(0), 0.f);
    EXPECT_EQ(lights.pmf(1), 0.f);
    EXPECT_EQ(lights.pmf(2), 1.f);
    Pcg32 g(1, 2);
    for (int i = 0; i < 100000; ++i) {
        LightSample s;
        ASSERT_TRUE(
            lights.sample(vec3(0.2f, 0.f, 0.2f), vec3(0.f), g.next_float(), vec2(g.next_float(), g.next_float()), s));
        ASSERT_NEAR(s.p.y, 2.f, 1e-6f);
        ASSERT_TRUE(std::isfinite(s.pdf));
    }
}

// Vertices up to 1.844e18 are valid, but a camera framing them (or any ray) can land beyond Embree's coordinate
// range, where Debian's Embree asserts and aborts (found by the fuzzer: `pathview render` of such an OBJ aborted).
// Such rays must simply hit nothing.
TEST(DegenerateGeometry, RaysBeyondEmbreeRangeHitNothingInsteadOfAborting) {
    auto scene = std::make_shared<Scene>(load_obj_from_string("v 0 0 0\nv 1 0 0\nv 0 1 1.8e18\nf 1 2 3\n", "far.obj"));
    ASSERT_EQ(scene->triangles.size(), 1u);
    const CameraDesc cam = scene->framing_camera();
    EXPECT_GT(max_component(glm::abs(cam.eye)), 1.844e18f);  // the case being tested
    uint64_t dropped = 0;
    const Film film = test::render_with_renderer(scene, cam, RenderSettings{}, 8, 8, 2, 1, &dropped);
    EXPECT_EQ(dropped, 0u);
    for (float v : film.mean().rgb) EXPECT_TRUE(std::isfinite(v));
    const Accel accel(*scene);
    Hit hit;
    Ray r;
    r.d = vec3(0.f, 0.f, -1.f);
    for (vec3 o : {vec3(0.f, 0.f, 1e20f), vec3(std::numeric_limits<float>::infinity()), vec3(std::nanf(""))}) {
        r.o = o;
        EXPECT_FALSE(accel.intersect(r, hit));
        EXPECT_FALSE(accel.occluded(r));
    }
    r.o = vec3(0.2f, 0.2f, 1.7e18f);  // just inside the range: still traced
    r.d = vec3(0.f, 0.f, -1.f);
    EXPECT_TRUE(accel.intersect(r, hit));
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

// ---------------------------------------------------------------- long accumulation

TEST(FilmAccumulation, HundredMillionSamplesStayExact) {
    Film film(1, 1);
    const vec3 v(0.1f, 3.3f, 1e-3f);
    const uint32_t n = 100000000u;
    for (uint32_t i = 0; i < n; ++i) film.add(0, 0, i, v);
    const FilmPixel& px = film.pixel(0, 0);
    ASSERT_EQ(px.n, n);
    const Image mean = film.mean();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean.rgb[size_t(c)], v[c], 1e-6 * v[c]) << "channel " << c;
    // Non-finite and negative samples are refused.
    EXPECT_FALSE(film.add(0, 0, n, vec3(std::nanf(""), 0.f, 0.f)));
    EXPECT_FALSE(film.add(0, 0, n, vec3(std::numeric_limits<float>::infinity())));
    EXPECT_FALSE(film.add(0, 0, n, vec3(-1.f, 0.f, 0.f)));
    EXPECT_EQ(film.pixel(0, 0).n, n);
}

}  // namespace
}  // namespace pv
