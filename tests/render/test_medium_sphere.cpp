// tests/render/test_medium_sphere.cpp: interior media (a material's "medium", docs/media.md): the medium stack of
// PathWalker, distance sampling, phase sampling and next-event estimation inside closed transmissive meshes.
//  * Transmittance: rays through an index-matched (eta 1) sphere holding a purely absorbing chromatic medium, under a
//    white sky, carry exp(-sigma_a x chord) per channel (Beer-Lambert over the chord the ray itself finds).
//  * Furnace: a glass sphere (eta 1.5) holding a non-absorbing chromatic medium, with a second glass sphere and a
//    second medium nested inside it, under a white sky (L = 1): the radiance field inside a region of index n is n^2,
//    uniform and isotropic, which non-absorbing scattering and lossless interfaces conserve, so every pixel is 1.
//  * Agreement: an emitter inside a glass sphere filled with an absorbing, scattering medium, the sphere in a thin
//    fog over a diffuse floor: BSDF-only, NEE and MIS, with and without roulette, give the same image mean.
// Test kinds: analytic; unit: MediumFlag; statistical: MediumSphereAgreement
#include <gtest/gtest.h>

#include <cmath>

#include "core/render/integrator.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

TEST(MediumSphereTransmittance, AbsorbingMediumFollowsBeerLambertAlongTheChord) {
    auto scene = std::make_shared<Scene>();
    Material m;
    m.bsdf = Dielectric{1.f};  // index-matched: the ray passes straight through both interfaces
    m.medium = HomogeneousMedium{vec3(0.3f, 0.9f, 2.f), vec3(0.f), 0.f};
    test::add_icosphere(*scene, vec3(0.f), 1.f, 3, test::add_material(*scene, m));
    scene->environment.background = vec3(1.f);
    const test::Tracer ts(scene);
    RenderSettings s;
    s.sampler = SamplerKind::Independent;
    Sampler sampler(5, SamplerKind::Independent);
    const float offsets[] = {0.f, 0.35f, 0.7f, 0.9f};
    const double k = test::sidak_k(3.0 * std::size(offsets));
    for (size_t i = 0; i < std::size(offsets); ++i) {
        Ray ray;
        ray.o = vec3(offsets[i], 0.1f, -3.f);
        ray.d = vec3(0.f, 0.f, 1.f);
        // The chord through the mesh: the entry, then the exit from just past it.
        Hit in, out;
        ASSERT_TRUE(ts.intersect(ray, in));
        Ray inside = ray;
        inside.o = ray.o + (in.t + 1e-3f) * ray.d;
        ASSERT_TRUE(ts.intersect(inside, out));
        const double chord = double(out.t) + 1e-3;
        test::Moments mom[3];
        PathCounters counters;
        for (uint32_t n = 0; n < 20000; ++n) {
            sampler.start(uvec2(uint32_t(i), 0u), n);
            const vec3 L = trace_path(ts, s, ray, sampler, counters);
            for (int c = 0; c < 3; ++c) mom[c].add(L[c]);
        }
        for (int c = 0; c < 3; ++c) {
            const double expected = std::exp(-double(m.medium.sigma_a[c]) * chord);
            EXPECT_LE(std::fabs(mom[c].mean - expected), k * mom[c].stderr_of_mean() + 1e-6)
                << "offset " << offsets[i] << ", channel " << c << ": mean " << mom[c].mean << ", expected " << expected
                << " (chord " << chord << ")";
        }
    }
}

// The walker's one flag (TraceableScene::has_media): off for a scene without media, so it does no medium work; on with
// the fog or a material's medium, and following the viewer's edits of either.
TEST(MediumFlag, OnlyScenesWithAMediumHaveMedia) {
    test::Tracer ts(test::cornell_box());
    EXPECT_FALSE(ts.has_media());
    ts.set_fog(HomogeneousMedium{vec3(0.f), vec3(0.01f), 0.f});
    EXPECT_TRUE(ts.has_media());
    ts.set_fog(HomogeneousMedium{});
    EXPECT_FALSE(ts.has_media());
    std::vector<Material> materials = ts.materials();
    materials[0].medium = HomogeneousMedium{vec3(0.1f), vec3(0.f), 0.f};
    ts.set_materials(materials);
    EXPECT_TRUE(ts.has_media());
    materials[0].medium = HomogeneousMedium{};
    ts.set_materials(materials);
    EXPECT_FALSE(ts.has_media());
}

struct Case {
    bool light_sampling, mis, rr;
};

void PrintTo(const Case& c, std::ostream* os) {
    *os << "nee=" << c.light_sampling << " mis=" << c.mis << " rr=" << c.rr;
}

std::string case_name(const testing::TestParamInfo<Case>& info) {
    const Case& c = info.param;
    return std::string(c.light_sampling ? (c.mis ? "Mis" : "Nee") : "Bsdf") + (c.rr ? "Rr" : "NoRr");
}

std::vector<Case> cases() {
    std::vector<Case> out;
    for (bool rr : {false, true}) {
        out.push_back({false, false, rr});
        out.push_back({true, false, rr});
        out.push_back({true, true, rr});
    }
    return out;
}

RenderSettings settings_of(const Case& c, uint32_t seed) {
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // the bounds use the i.i.d. sample variance
    s.light_sampling = c.light_sampling;
    s.mis = c.mis;
    s.russian_roulette = c.rr;
    s.max_depth = 1024;
    s.seed = seed + (c.light_sampling ? 4 : 0) + (c.mis ? 2 : 0) + (c.rr ? 1 : 0);
    return s;
}

const std::shared_ptr<const Scene>& nested_furnace() {
    static const std::shared_ptr<const Scene> scene = [] {
        auto s = std::make_shared<Scene>();
        Material outer;
        outer.bsdf = Dielectric{1.5f};
        outer.medium = HomogeneousMedium{vec3(0.f), vec3(1.5f, 0.7f, 0.3f), 0.4f};
        Material inner;
        inner.bsdf = Dielectric{1.2f / 1.5f};  // n = 1.2 inside, n = 1.5 around it
        inner.medium = HomogeneousMedium{vec3(0.f), vec3(0.5f, 2.f, 1.f), -0.3f};
        test::add_icosphere(*s, vec3(0.f), 1.f, 2, test::add_material(*s, outer));
        test::add_icosphere(*s, vec3(0.1f, 0.f, 0.f), 0.5f, 2, test::add_material(*s, inner));
        s->environment.background = vec3(1.f);
        return std::shared_ptr<const Scene>(s);
    }();
    return scene;
}

class MediumSphereFurnace : public testing::TestWithParam<Case> {};

TEST_P(MediumSphereFurnace, NonAbsorbingNestedMediaKeepTheSkysRadiance) {
    static const test::Tracer tracer(nested_furnace());
    CameraDesc cam;
    cam.eye = vec3(0.3f, 0.4f, 3.f);
    cam.target = vec3(0.f);
    cam.vfov_deg = 30.f;  // the sphere fills most of the image
    const RenderSettings s = settings_of(GetParam(), 101);
    test::Moments mom[3];
    tracer.for_each_sample(cam, s, 8, 8, 64, [&](int, int, uint32_t, vec3 v) {
        for (int ch = 0; ch < 3; ++ch) mom[ch].add(v[ch]);
    });
    const double k = test::sidak_k(double(cases().size() * 3));
    for (int ch = 0; ch < 3; ++ch) {
        const double se = mom[ch].stderr_of_mean();
        EXPECT_LE(std::fabs(mom[ch].mean - 1.0), k * se + 1e-5)
            << "channel " << ch << ": mean " << mom[ch].mean << ", stderr " << se << ", k " << k;
    }
}

INSTANTIATE_TEST_SUITE_P(AllSwitches, MediumSphereFurnace, testing::ValuesIn(cases()), case_name);

const std::shared_ptr<const Scene>& lamp_in_medium() {
    static const std::shared_ptr<const Scene> scene = [] {
        auto s = std::make_shared<Scene>();
        Material glass;
        glass.bsdf = Dielectric{1.3f};
        glass.medium = HomogeneousMedium::from_albedo(vec3(0.9f, 0.7f, 0.5f), 1.5f, 0.3f);
        test::add_icosphere(*s, vec3(0.f), 1.f, 2, test::add_material(*s, glass));
        Material lamp;
        lamp.bsdf = Lambertian{vec3(0.f)};
        lamp.emission = vec3(4.f);
        lamp.two_sided_emission = true;
        const uint32_t l = test::add_material(*s, lamp);
        test::add_quad(*s, vec3(-0.2f, 0.1f, -0.2f), vec3(0.2f, 0.1f, -0.2f), vec3(0.2f, 0.1f, 0.2f),
                       vec3(-0.2f, 0.1f, 0.2f), l);
        Material floor;
        floor.bsdf = Lambertian{vec3(0.6f)};
        test::add_quad(*s, vec3(-4.f, -1.2f, 4.f), vec3(4.f, -1.2f, 4.f), vec3(4.f, -1.2f, -4.f),
                       vec3(-4.f, -1.2f, -4.f), test::add_material(*s, floor));
        s->environment.background = vec3(0.f);
        s->fog = HomogeneousMedium{vec3(0.02f), vec3(0.1f), 0.f};
        return std::shared_ptr<const Scene>(s);
    }();
    return scene;
}

// The image mean per channel and its variance, from a render with case c.
struct Estimate {
    double mean[3], var[3];
};

Estimate estimate(const Case& c) {
    static const test::Tracer tracer(lamp_in_medium());
    CameraDesc cam;
    cam.eye = vec3(0.5f, 1.2f, 3.5f);
    cam.target = vec3(0.f, -0.3f, 0.f);
    cam.vfov_deg = 50.f;
    const Film film = tracer.render(cam, settings_of(c, 201), 12, 12, 64);
    const test::PixelStats st = test::PixelStats::from_film(film);
    Estimate e{};
    const size_t pixels = st.size() / 3;
    for (size_t i = 0; i < st.size(); ++i) {
        e.mean[i % 3] += st.mean[i] / double(pixels);
        e.var[i % 3] += st.var_mean[i] / double(pixels * pixels);
    }
    return e;
}

class MediumSphereAgreement : public testing::TestWithParam<Case> {};

// Each estimator against MIS without roulette (independent renders): a two-sample z test per channel.
TEST_P(MediumSphereAgreement, EstimatorsAgreeInsideAndAroundTheMedium) {
    const Case c = GetParam();
    if (c.light_sampling && c.mis && !c.rr) GTEST_SKIP() << "the reference";
    static const Estimate ref = estimate(Case{true, true, false});
    const Estimate e = estimate(c);
    const double k = test::sidak_k(double((cases().size() - 1) * 3));
    for (int ch = 0; ch < 3; ++ch) {
        EXPECT_GT(ref.mean[ch], 1e-3) << "the lamp lights the image";
        const double se = std::sqrt(e.var[ch] + ref.var[ch]);
        EXPECT_LE(std::fabs(e.mean[ch] - ref.mean[ch]), k * se)
            << "channel " << ch << ": " << e.mean[ch] << " vs " << ref.mean[ch] << ", se " << se;
    }
}

INSTANTIATE_TEST_SUITE_P(AllSwitches, MediumSphereAgreement, testing::ValuesIn(cases()), case_name);

}  // namespace
}  // namespace pv
