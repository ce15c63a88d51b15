// tests/render/test_direct.cpp: direct lighting of a diffuse plane by a polygonal area light (closed-form irradiance),
// against Lambert's formula for the irradiance from a uniform polygon:
//     E = (L / 2) |sum_i acos(v_i . v_i+1) (n . normalize(v_i x v_i+1))|,  pixel = (rho / pi) E,
// with v_i the unit vectors from the receiver point to the polygon's vertices. max_depth 1 (direct only), with
// NEE only, BSDF sampling only and MIS, with the independent and the Sobol sampler. Camera rays go through pixel
// centres so each pixel has one receiver point and an exact reference. Pass: per-pixel |mean - ref| <= k stderr (Sidak
// over every pixel of every render) and the image mean within k stderr (Sidak over the renders).
// Test kinds: analytic
#include <gtest/gtest.h>

#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

double lambert_polygon_irradiance(const std::vector<dvec3>& poly, dvec3 x, dvec3 n, double radiance) {
    double sum = 0.0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const dvec3 a = glm::normalize(poly[i] - x), b = glm::normalize(poly[(i + 1) % poly.size()] - x);
        const double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
        sum += angle * glm::dot(n, glm::normalize(glm::cross(a, b)));
    }
    return 0.5 * radiance * std::fabs(sum);
}

// The closed form for a parallel rectangle checks the polygon formula itself: catalog example a=1, b=2, c=1.5
// gives pi F = 0.38440 below a corner and 1.53762 below the centre of the 2a x 2b rectangle (L = 1).
TEST(DirectLight, LambertFormulaMatchesRectangleClosedForm) {
    const dvec3 n(0, 0, 1);
    const double corner =
        lambert_polygon_irradiance({{0, 0, 1.5}, {1, 0, 1.5}, {1, 2, 1.5}, {0, 2, 1.5}}, dvec3(0), n, 1);
    EXPECT_NEAR(corner, 0.384404, 2e-6);
    const double centre =
        lambert_polygon_irradiance({{-1, -2, 1.5}, {1, -2, 1.5}, {1, 2, 1.5}, {-1, 2, 1.5}}, dvec3(0), n, 1);
    EXPECT_NEAR(centre, 1.53762, 2e-5);
    EXPECT_NEAR(centre, 4 * corner, 1e-9);
}

struct LightShape {
    const char* name;
    std::vector<vec3> polygon;  // convex, wound so its normal (p1-p0) x (p2-p0) faces the plane
};

constexpr int kW = 16, kH = 16;
constexpr float kRho = 0.8f, kLe = 2.f;

std::vector<LightShape> light_shapes() {
    return {{"rectangle", {vec3(-1, -2, 1.5f), vec3(-1, 2, 1.5f), vec3(1, 2, 1.5f), vec3(1, -2, 1.5f)}},
            {"tilted triangle", {vec3(-1.5f, -0.5f, 0.6f), vec3(0.5f, 1.5f, 1.8f), vec3(1.2f, -1.f, 1.1f)}}};
}

TEST(DirectLight, PlaneUnderPolygonLightMatchesLambertFormula) {
    const auto shapes = light_shapes();
    struct Mode {
        const char* name;
        bool nee, mis;
    };
    const Mode modes[] = {{"nee", true, false}, {"bsdf", false, false}, {"mis", true, true}};
    // Every estimator with each sampler (a Sobol sequence's correlated samples make the sample variance an
    // overestimate of the mean's error, so the bound only gets more conservative).
    const SamplerKind samplers[] = {SamplerKind::Independent, SamplerKind::Sobol};
    const double renders = double(shapes.size() * std::size(modes) * std::size(samplers));
    const double k_pixel = test::sidak_k(renders * kW * kH);
    const double k_mean = test::sidak_k(renders);
    for (const LightShape& shape : shapes) {
        auto scene = std::make_shared<Scene>();
        Material plane, light;
        plane.bsdf = Lambertian{vec3(kRho)};
        light.bsdf = Lambertian{vec3(0.f)};
        light.emission = vec3(kLe);
        const uint32_t mp = test::add_material(*scene, plane), ml = test::add_material(*scene, light);
        test::add_quad(*scene, vec3(-20, -20, 0), vec3(20, -20, 0), vec3(20, 20, 0), vec3(-20, 20, 0), mp);
        for (size_t i = 1; i + 1 < shape.polygon.size(); ++i)
            scene->add_triangle(shape.polygon[0], shape.polygon[i], shape.polygon[i + 1], ml);
        const vec3 ln = glm::cross(shape.polygon[1] - shape.polygon[0], shape.polygon[2] - shape.polygon[0]);
        ASSERT_LT(ln.z, 0.f) << "the light must face the plane";
        const test::Tracer tracer(scene);
        CameraDesc cam;
        cam.eye = vec3(0.1f, -0.2f, 0.5f);
        cam.target = vec3(0.2f, 0.1f, 0.f);
        cam.up = vec3(0, 1, 0);
        cam.vfov_deg = 90.f;
        // Reference per pixel: the receiver point of the pixel-centre ray.
        const Camera camera(cam, kW, kH);
        std::vector<double> ref(size_t(kW) * kH);
        std::vector<dvec3> poly;
        for (const vec3& p : shape.polygon) poly.push_back(dvec3(p));
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const Ray r = camera.generate(vec2(x + 0.5f, y + 0.5f), vec2(0.5f));
                Hit hit;
                ASSERT_TRUE(tracer.accel().intersect(r, hit));
                ASSERT_LT(hit.prim, 2u) << "every pixel must see the plane";
                const dvec3 p = dvec3(r.o) + double(hit.t) * dvec3(r.d);
                ref[size_t(y) * kW + x] =
                    kRho / M_PI * lambert_polygon_irradiance(poly, dvec3(p.x, p.y, 0.0), dvec3(0, 0, 1), kLe);
            }
        for (const SamplerKind kind : samplers) {
            for (const Mode& mode : modes) {
                RenderSettings s;
                s.sampler = kind;
                s.light_sampling = mode.nee;
                s.mis = mode.mis;
                s.max_depth = 1;
                s.seed = 99 + (mode.nee ? 1 : 0) + (mode.mis ? 2 : 0);
                const Film film = tracer.render(cam, s, kW, kH, 256, /*pixel_centre=*/true);
                const test::PixelStats st = test::PixelStats::from_film(film);
                double diff_sum = 0.0, var_sum = 0.0, worst_z = 0.0;
                int fails = 0;
                for (int i = 0; i < kW * kH; ++i) {
                    const double m = st.mean[size_t(i) * 3], v = st.var_mean[size_t(i) * 3];
                    const double z = (m - ref[size_t(i)]) / std::sqrt(std::max(v, 1e-30));
                    worst_z = std::max(worst_z, std::fabs(z));
                    fails += std::fabs(z) > k_pixel;
                    diff_sum += m - ref[size_t(i)];
                    var_sum += v;
                }
                const std::string where = std::string(shape.name) + ", " + mode.name + ", " + sampler_name(kind);
                EXPECT_EQ(fails, 0) << where << ": worst pixel z = " << worst_z << " > k = " << k_pixel;
                const double z_mean = diff_sum / std::sqrt(var_sum);
                EXPECT_LE(std::fabs(z_mean), k_mean) << where << ": image-mean z = " << z_mean;
            }
        }
    }
}

}  // namespace
}  // namespace pv
