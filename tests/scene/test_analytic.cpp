// tests/scene/test_analytic.cpp: scenes with a closed-form answer (the white furnace around a convex object, and the
// closed diffuse enclosure with uniform emission).
//  * White furnace: a closed convex sphere mesh in a constant environment L. Lambert albedo rho returns rho*L;
//    with BSDF-only sampling and no roulette every single sample is exact (zero variance).
//  * Closed emissive enclosure (inward sphere, Ke = 0.5, Kd = 0.5): L = Le / (1 - rho) = 1 and, with at most D
//    scattering events, L_D = Le (1 - rho^(D+1)) / (1 - rho), for every light_sampling/mis/rr combination.
// Statistical bounds: |mean - expected| <= k * stderr, stderr from the sample variance, k Sidak-corrected over
// the number of statistical tests in the family (alpha = 0.01).
// Test kinds: analytic
#include <gtest/gtest.h>

#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

using test::add_icosphere;
using test::add_material;

constexpr int kFurnaceW = 16, kFurnaceH = 16;

std::shared_ptr<Scene> furnace_scene(const Bsdf& bsdf, vec3 background) {
    auto scene = std::make_shared<Scene>();
    Material m;
    m.bsdf = bsdf;
    add_icosphere(*scene, vec3(0.f), 1.f, 2, add_material(*scene, m));
    scene->environment.background = background;
    return scene;
}

CameraDesc furnace_camera() {
    CameraDesc c;
    c.eye = vec3(0.3f, 0.4f, 3.5f);
    c.target = vec3(0.f);
    c.vfov_deg = 45.f;
    return c;
}

// Every sample of the zero-variance furnace is background (missed the sphere) or rho*background (hit it).
void expect_zero_variance_furnace(const Bsdf& bsdf, float rho, int spp) {
    const vec3 L(0.7f, 1.3f, 2.f);
    const test::Tracer tracer(furnace_scene(bsdf, L));
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    s.light_sampling = false;
    s.mis = false;
    s.russian_roulette = false;
    s.seed = 5;
    size_t hits = 0, misses = 0, bad = 0;
    vec3 worst(0.f);
    tracer.for_each_sample(furnace_camera(), s, kFurnaceW, kFurnaceH, spp, [&](int, int, uint32_t, vec3 v) {
        const bool is_bg = glm::all(glm::lessThanEqual(glm::abs(v - L), 1e-5f * L));
        const bool is_obj = glm::all(glm::lessThanEqual(glm::abs(v - rho * L), 1e-5f * L));
        if (is_obj) {
            ++hits;  // (for rho = 1 both hold: counted as hits)
        } else if (is_bg) {
            ++misses;
        } else if (++bad == 1) {
            worst = v;
        }
    });
    EXPECT_EQ(bad, 0u) << "first inexact sample " << worst.x << " " << worst.y << " " << worst.z;
    EXPECT_GT(hits, size_t(kFurnaceW * kFurnaceH * spp / 4));
    if (rho != 1.f) {
        EXPECT_GT(misses, 0u);
    }
}

TEST(Furnace, LambertAlbedo1EverySampleExact) { expect_zero_variance_furnace(Lambertian{vec3(1.f)}, 1.f, 16); }
TEST(Furnace, LambertAlbedoHalfEverySampleExact) { expect_zero_variance_furnace(Lambertian{vec3(0.5f)}, 0.5f, 16); }
TEST(Furnace, MirrorSphereEverySampleExact) { expect_zero_variance_furnace(Mirror{vec3(1.f)}, 1.f, 8); }

// The same through the Renderer: per-pixel variance 0 and every sphere pixel's mean equal (float eps).
TEST(Furnace, RendererPixelsHaveZeroVariance) {
    const vec3 L(1.f);
    auto scene = furnace_scene(Lambertian{vec3(1.f)}, L);
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    s.light_sampling = false;
    s.russian_roulette = false;
    const Film film = test::render_with_renderer(scene, furnace_camera(), s, kFurnaceW, kFurnaceH, 16);
    for (int y = 0; y < kFurnaceH; ++y)
        for (int x = 0; x < kFurnaceW; ++x) {
            const FilmPixel& px = film.pixel(x, y);
            ASSERT_EQ(px.n, 16u);
            for (int c = 0; c < 3; ++c) {
                const double m = px.sum[c] / px.n;
                EXPECT_NEAR(m, 1.0, 1e-5) << x << "," << y;
                EXPECT_NEAR(px.sum_sq[c] / px.n - m * m, 0.0, 1e-5) << x << "," << y;
            }
        }
}

// With roulette (and the NEE/MIS switches on, which have no emitters to sample here), the mean is unbiased.
// Family: these 3 tests.
void expect_unbiased_furnace(const Bsdf& bsdf, float rho, bool rr, int spp) {
    const vec3 L(1.f);
    const test::Tracer tracer(furnace_scene(bsdf, L));
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    s.russian_roulette = rr;
    s.seed = 17;
    // Only samples whose camera ray hits the sphere (the background is exact): trace the camera ray to tell.
    const Camera camera(furnace_camera(), kFurnaceW, kFurnaceH);
    test::Moments mom;
    Sampler sampler(s.seed);
    tracer.for_each_sample(furnace_camera(), s, kFurnaceW, kFurnaceH, spp, [&](int x, int y, uint32_t i, vec3 v) {
        Hit hit;
        if (tracer.accel().intersect(camera_ray(camera, sampler, x, y, i), hit)) mom.add(v.x);
    });
    const double k = test::sidak_k(3);
    ASSERT_GT(mom.n, 1000u);
    EXPECT_LE(std::fabs(mom.mean - rho), k * mom.stderr_of_mean() + 1e-6)
        << "mean " << mom.mean << " stderr " << mom.stderr_of_mean();
}
TEST(Furnace, LambertHalfWithRouletteUnbiased) { expect_unbiased_furnace(Lambertian{vec3(0.5f)}, 0.5f, true, 64); }
// A smooth glass sphere (R + T = 1, no absorption) returns L (catalog 2.1, non-convex paths inside).
TEST(Furnace, GlassSphereReturnsL) { expect_unbiased_furnace(Dielectric{1.5f}, 1.f, false, 32); }
TEST(Furnace, GlassSphereWithRouletteReturnsL) { expect_unbiased_furnace(Dielectric{1.5f}, 1.f, true, 32); }

// ---------------------------------------------------------------- closed emissive enclosure

struct EnclosureCase {
    bool light_sampling, mis, rr;
    int depth;  // max_depth; 1024 stands for "unbounded"
};

void PrintTo(const EnclosureCase& c, std::ostream* os) {
    *os << "nee=" << c.light_sampling << " mis=" << c.mis << " rr=" << c.rr << " max_depth=" << c.depth;
}

std::string case_name(const testing::TestParamInfo<EnclosureCase>& info) {
    const EnclosureCase& c = info.param;
    return std::string(c.light_sampling ? (c.mis ? "Mis" : "Nee") : "Bsdf") + (c.rr ? "Rr" : "NoRr") + "Depth" +
           (c.depth >= 1024 ? std::string("Inf") : std::to_string(c.depth));
}

std::vector<EnclosureCase> enclosure_cases() {
    std::vector<EnclosureCase> out;
    for (int d : {0, 1, 2, 4, 8, 1024})
        for (bool rr : {false, true}) {
            out.push_back({false, false, rr, d});
            out.push_back({true, false, rr, d});
            out.push_back({true, true, rr, d});
        }
    return out;
}

const std::shared_ptr<const Scene>& enclosure_scene() {
    static const std::shared_ptr<const Scene> scene = [] {
        auto s = std::make_shared<Scene>();
        Material m;
        m.bsdf = Lambertian{vec3(0.5f)};
        m.emission = vec3(0.5f);
        add_icosphere(*s, vec3(0.f), 1.f, 2, add_material(*s, m), /*inward=*/true);
        return std::shared_ptr<const Scene>(s);
    }();
    return scene;
}

class Enclosure : public testing::TestWithParam<EnclosureCase> {};

TEST_P(Enclosure, RadianceMatchesClosedForm) {
    const EnclosureCase c = GetParam();
    const double le = 0.5, rho = 0.5;
    const double expected = c.depth >= 1024 ? le / (1 - rho) : le * (1 - std::pow(rho, c.depth + 1)) / (1 - rho);
    static const test::Tracer tracer(enclosure_scene());
    CameraDesc cam;
    cam.eye = vec3(0.1f, -0.2f, 0.05f);
    cam.target = vec3(0.3f, 0.2f, -1.f);
    cam.vfov_deg = 70.f;
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    s.light_sampling = c.light_sampling;
    s.mis = c.mis;
    s.russian_roulette = c.rr;
    s.max_depth = c.depth;
    s.seed = 1000 + uint32_t(c.depth) * 8 + (c.light_sampling ? 4 : 0) + (c.mis ? 2 : 0) + (c.rr ? 1 : 0);
    const bool zero_variance = !c.light_sampling && !c.rr;
    const int spp = zero_variance ? 4 : (c.depth >= 1024 && !c.rr ? 64 : 256);
    test::Moments mom[3];
    size_t inexact = 0;
    vec3 first_bad(0.f);
    tracer.for_each_sample(cam, s, 8, 8, spp, [&](int, int, uint32_t, vec3 v) {
        for (int ch = 0; ch < 3; ++ch) mom[ch].add(v[ch]);
        if (zero_variance && !(std::fabs(v.x - expected) <= 1e-5 * expected) && ++inexact == 1) first_bad = v;
    });
    if (zero_variance) {
        // BSDF-only without roulette: the weight f cos / pdf is exactly rho at every bounce.
        EXPECT_EQ(inexact, 0u) << "first inexact sample " << first_bad.x << ", expected " << expected;
    }
    // Family: all enclosure cases x 3 channels.
    const double k = test::sidak_k(double(enclosure_cases().size() * 3));
    for (int ch = 0; ch < 3; ++ch) {
        const double se = mom[ch].stderr_of_mean();
        EXPECT_LE(std::fabs(mom[ch].mean - expected), k * se + 1e-5 * expected)
            << "channel " << ch << ": mean " << mom[ch].mean << ", expected " << expected << ", stderr " << se << ", k "
            << k;
    }
}

INSTANTIATE_TEST_SUITE_P(AllSwitches, Enclosure, testing::ValuesIn(enclosure_cases()), case_name);

}  // namespace
}  // namespace pv
