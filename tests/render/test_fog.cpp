// tests/render/test_fog.cpp: the path tracer in a global medium (Scene::fog, core/scene/medium.h).
//  * White furnace in fog: the closed emissive enclosure (inward sphere, Le = 0.5, Lambert 0.5: L = Le / (1 - rho)
//    = 1) filled with a non-absorbing (albedo 1) chromatic, forward-scattering fog keeps L = 1 in every channel: the
//    radiance field is uniform and isotropic and such a medium conserves it. Every estimator (BSDF-only, NEE, MIS,
//    with and without roulette) is checked against 1 within a Sidak-corrected interval from the sample variance;
//    distance sampling, phase sampling, NEE from medium points with the fog's transmittance and its MIS with phase
//    sampling all enter.
// Test kinds: analytic
#include <gtest/gtest.h>

#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

struct FogCase {
    bool light_sampling, mis, rr;
};

void PrintTo(const FogCase& c, std::ostream* os) {
    *os << "nee=" << c.light_sampling << " mis=" << c.mis << " rr=" << c.rr;
}

std::string fog_case_name(const testing::TestParamInfo<FogCase>& info) {
    const FogCase& c = info.param;
    return std::string(c.light_sampling ? (c.mis ? "Mis" : "Nee") : "Bsdf") + (c.rr ? "Rr" : "NoRr");
}

std::vector<FogCase> fog_cases() {
    std::vector<FogCase> out;
    for (bool rr : {false, true}) {
        out.push_back({false, false, rr});
        out.push_back({true, false, rr});
        out.push_back({true, true, rr});
    }
    return out;
}

const std::shared_ptr<const Scene>& fogged_enclosure() {
    static const std::shared_ptr<const Scene> scene = [] {
        auto s = std::make_shared<Scene>();
        Material m;
        m.bsdf = Lambertian{vec3(0.5f)};
        m.emission = vec3(0.5f);
        test::add_icosphere(*s, vec3(0.f), 1.f, 2, test::add_material(*s, m), /*inward=*/true);
        s->fog = HomogeneousMedium{vec3(0.f), vec3(2.f, 0.8f, 0.3f), 0.5f};
        return std::shared_ptr<const Scene>(s);
    }();
    return scene;
}

class FogFurnace : public testing::TestWithParam<FogCase> {};

TEST_P(FogFurnace, NonAbsorbingFogKeepsTheEnclosuresRadiance) {
    const FogCase c = GetParam();
    static const test::Tracer tracer(fogged_enclosure());
    CameraDesc cam;
    cam.eye = vec3(0.1f, -0.2f, 0.05f);
    cam.target = vec3(0.3f, 0.2f, -1.f);
    cam.vfov_deg = 70.f;
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // the bounds use the i.i.d. sample variance
    s.light_sampling = c.light_sampling;
    s.mis = c.mis;
    s.russian_roulette = c.rr;
    s.max_depth = 1024;
    s.seed = 77 + (c.light_sampling ? 4 : 0) + (c.mis ? 2 : 0) + (c.rr ? 1 : 0);
    test::Moments mom[3];
    tracer.for_each_sample(cam, s, 8, 8, c.rr ? 256 : 64, [&](int, int, uint32_t, vec3 v) {
        for (int ch = 0; ch < 3; ++ch) mom[ch].add(v[ch]);
    });
    const double k = test::sidak_k(double(fog_cases().size() * 3));
    for (int ch = 0; ch < 3; ++ch) {
        const double se = mom[ch].stderr_of_mean();
        EXPECT_LE(std::fabs(mom[ch].mean - 1.0), k * se + 1e-5)
            << "channel " << ch << ": mean " << mom[ch].mean << ", stderr " << se << ", k " << k;
    }
}

INSTANTIATE_TEST_SUITE_P(AllSwitches, FogFurnace, testing::ValuesIn(fog_cases()), fog_case_name);

}  // namespace
}  // namespace pv
