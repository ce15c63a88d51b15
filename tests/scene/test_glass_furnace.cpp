// tests/scene/test_glass_furnace.cpp: smooth glass with interpolated normals conserves energy (issue 10, item 4).
// A coarse (8 x 6) smooth-shaded glass sphere in a white furnace (L = 1 everywhere): every path that leaves it
// carries exactly 1 (a refraction in scales radiance by 1/eta^2 and the refraction out by eta^2), so every pixel is
// 1. Where the shading normal disagrees with the facet, a reflected or refracted direction can cross the facet's
// plane on the wrong side; a path that ends there is a dark rim at the silhouette. And total internal reflection
// about interpolated normals can keep a path circling inside until the depth cap. Both were 2.4% of the paths
// here (depth cap 1024, roulette off), darkest pixel 0.25.
// Test kinds: analytic
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

TEST(GlassFurnace, CoarseSmoothGlassSphereIsInvisibleInAWhiteFurnace) {
    for (const float eta : {1.5f, 1.f / 1.5f}) {
        auto scene = std::make_shared<Scene>();
        Material glass;
        glass.bsdf = Dielectric{eta};
        test::add_uv_sphere(*scene, vec3(0.f), 1.f, 8, 6, test::add_material(*scene, glass), /*smooth=*/true);
        scene->environment.background = vec3(1.f);
        const test::Tracer tracer(scene);
        CameraDesc cam;
        cam.eye = vec3(0.4f, 0.5f, 3.2f);
        cam.target = vec3(0.f);
        cam.vfov_deg = 42.f;  // the whole sphere and its silhouette
        const int w = 24, h = 24, spp = 32;
        for (const bool rr : {false, true}) {
            RenderSettings s;
            s.sampler = SamplerKind::Independent;  // i.i.d. samples for the variance
            s.russian_roulette = rr;
            s.seed = rr ? 2 : 1;
            Film film(w, h);
            size_t lost = 0, samples = 0;
            tracer.for_each_sample(cam, s, w, h, spp, [&](int x, int y, uint32_t i, vec3 v) {
                ++samples;
                // Without roulette every sample is 1 up to float rounding, or 0 where its path was cut.
                if (!rr && !(std::fabs(v.y - 1.f) < 1e-4f)) ++lost;
                film.add(x, y, i, v);
            });
            const auto st = test::PixelStats::from_film(film);
            const double k = test::sidak_k(double(w * h));
            int dark = 0;
            double darkest = 2.0;
            for (size_t i = 1; i < st.size(); i += 3) {
                darkest = std::min(darkest, st.mean[i]);
                // 1e-5: float rounding of the exact samples (eta^2 / eta^2 over a few refractions).
                if (st.mean[i] + k * std::sqrt(st.var_mean[i]) < 1.0 - 1e-5) ++dark;
            }
            const char* what = rr ? "roulette on" : "roulette off";
            EXPECT_EQ(dark, 0) << "eta " << eta << ", " << what << ": darkest pixel " << darkest;
            if (!rr) {
                EXPECT_EQ(lost, 0u) << "eta " << eta << ": " << lost << " of " << samples << " paths lost";
            }
            EXPECT_NEAR(st.total_mean(), 1.0, k * std::sqrt(st.total_mean_variance()) + 1e-5)
                << "eta " << eta << ", " << what;
        }
    }
}

}  // namespace
}  // namespace pv
