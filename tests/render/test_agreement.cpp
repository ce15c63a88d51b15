// tests/render/test_agreement.cpp: estimator agreement (roulette on/off, NEE vs BSDF-only vs MIS, two noisy images
// compared statistically, the Veach MIS scene). Every switch combination must converge to the same image.
//  * Cornell box (built-in scene), 24x24: BSDF-only, NEE, MIS (roulette on) and MIS with roulette off, independent
//    seeds; per-pixel Welch t with Sidak k over the pixel-channels (at most 0.25% above k, none above k + 2) and
//    the total-mean test (|z| < 3.29) for each pair.
//  * A Veach-style MIS scene built in code: four glossy plates of increasing roughness under four spherical
//    lights of equal power and very different sizes. BSDF-only sampling of the small lights on rough plates is
//    so heavy-tailed that per-pixel sample variances are unreliable at test budgets, so the images are compared
//    per region (each plate split into 4 parts, region means over many pixels and samples, Welch z with Sidak),
//    and MIS must be at least about as good as the better strategy on each plate:
//    relMSE(MIS) <= 1.1 min(relMSE(NEE), relMSE(BSDF)), relMSE = mean over the plate's pixels of
//    Var(pixel mean) / (ref^2 + 0.01) averaged over several seeds (the estimators are unbiased, so MSE = variance).
// Test kinds: statistical
#include <gtest/gtest.h>

#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

test::PixelStats render_stats(std::shared_ptr<const Scene> scene, const CameraDesc& cam, const RenderSettings& s, int w,
                              int h, int spp) {
    return test::PixelStats::from_film(test::render_with_renderer(std::move(scene), cam, s, w, h, spp, 2));
}

RenderSettings make_settings(bool nee, bool mis, bool rr, uint32_t seed, int max_depth = 1024) {
    RenderSettings s;
    s.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    s.light_sampling = nee;
    s.mis = mis;
    s.russian_roulette = rr;
    s.seed = seed;
    s.max_depth = max_depth;
    return s;
}

// Region means over blocks of pixels: a heavy-tailed estimator (BSDF-only sampling of a small light reaching a
// shadowed pixel only after two bounces) hits the light too rarely per pixel at test budgets for per-pixel sample
// variances to be trusted, so it is compared per block of pixels with many more samples.
struct RegionStats {
    std::vector<double> mean, var;  // per region x channel
};

RegionStats region_stats(const test::PixelStats& st, const std::vector<int>& region, int nregions) {
    RegionStats r;
    r.mean.assign(size_t(nregions) * 3, 0.0);
    r.var.assign(size_t(nregions) * 3, 0.0);
    std::vector<double> count(size_t(nregions), 0.0);
    for (size_t i = 0; i < region.size(); ++i)
        if (region[i] >= 0) count[size_t(region[i])] += 1.0;
    for (size_t i = 0; i < region.size(); ++i) {
        if (region[i] < 0) continue;
        const size_t g = size_t(region[i]);
        for (int c = 0; c < 3; ++c) {
            r.mean[g * 3 + c] += st.mean[i * 3 + c] / count[g];
            r.var[g * 3 + c] += st.var_mean[i * 3 + c] / (count[g] * count[g]);
        }
    }
    return r;
}

// Welch z per region-channel, Sidak k over `family` tests; returns the failures as text.
std::string compare_regions(const RegionStats& a, const RegionStats& b, double family) {
    const double k = test::sidak_k(family);
    std::string out;
    for (size_t i = 0; i < a.mean.size(); ++i) {
        const double se = std::sqrt(a.var[i] + b.var[i]);
        const double z = se > 0 ? (a.mean[i] - b.mean[i]) / se : (a.mean[i] == b.mean[i] ? 0.0 : 1e9);
        if (std::fabs(z) > k)
            out += " region " + std::to_string(i / 3) + " channel " + std::to_string(i % 3) + ": " +
                   std::to_string(a.mean[i]) + " vs " + std::to_string(b.mean[i]) + " (z " + std::to_string(z) +
                   ", k " + std::to_string(k) + ");";
    }
    return out;
}

TEST(AgreementCornell, NeeMisAndRouletteAgreePerPixel) {
    auto scene = test::cornell_box();
    const int w = 24, h = 24;
    const auto nee = render_stats(scene, scene->camera, make_settings(true, false, true, 12), w, h, 256);
    const auto mis = render_stats(scene, scene->camera, make_settings(true, true, true, 13), w, h, 256);
    const auto mis_no_rr = render_stats(scene, scene->camera, make_settings(true, true, false, 14, 64), w, h, 128);
    const auto nee_no_rr = render_stats(scene, scene->camera, make_settings(true, false, false, 15, 64), w, h, 128);
    const std::pair<const char*, std::pair<const test::PixelStats*, const test::PixelStats*>> pairs[] = {
        {"MIS vs NEE", {&mis, &nee}},
        {"MIS roulette on vs off", {&mis, &mis_no_rr}},
        {"NEE roulette on vs off", {&nee, &nee_no_rr}}};
    for (const auto& [name, p] : pairs) {
        const test::ImageComparison c = test::compare_images(*p.first, *p.second);
        EXPECT_TRUE(c.passed) << name << ": " << c.describe();
    }
    EXPECT_GT(mis.total_mean(), 0.01);
}

TEST(AgreementCornell, BsdfOnlyAgreesPerBlockAndInTotal) {
    auto scene = test::cornell_box();
    const int w = 16, h = 16, block = 4, nb = (w / block) * (h / block);
    std::vector<int> region(size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) region[size_t(y) * w + x] = (y / block) * (w / block) + x / block;
    const auto bsdf = render_stats(scene, scene->camera, make_settings(false, false, true, 21), w, h, 2048);
    const auto bsdf_no_rr = render_stats(scene, scene->camera, make_settings(false, false, false, 22, 64), w, h, 1024);
    const auto mis = render_stats(scene, scene->camera, make_settings(true, true, true, 23), w, h, 512);
    const double family = 2.0 * nb * 3;
    const auto rb = region_stats(bsdf, region, nb), rbn = region_stats(bsdf_no_rr, region, nb),
               rm = region_stats(mis, region, nb);
    EXPECT_EQ(compare_regions(rm, rb, family), "") << "MIS vs BSDF-only";
    EXPECT_EQ(compare_regions(rb, rbn, family), "") << "BSDF-only roulette on vs off";
    for (const auto* other : {&bsdf, &bsdf_no_rr}) {
        const double z = (mis.total_mean() - other->total_mean()) /
                         std::sqrt(mis.total_mean_variance() + other->total_mean_variance());
        EXPECT_LT(std::fabs(z), 3.29) << "total-mean z";
    }
}

// ---------------------------------------------------------------- Veach MIS scene

struct VeachScene {
    std::shared_ptr<Scene> scene = std::make_shared<Scene>();
    CameraDesc camera;
    std::vector<uint32_t> plate_material;  // material of plate j
    static constexpr float kAlpha[4] = {0.02f, 0.06f, 0.15f, 0.4f};

    VeachScene() {
        // Lights of equal power (r^2 L = 1) along x, high above the plates.
        const float radius[4] = {0.1f, 0.2f, 0.4f, 0.8f};
        const float xs[4] = {-3.75f, -1.25f, 1.25f, 3.75f};
        for (int i = 0; i < 4; ++i) {
            Material m;
            m.bsdf = Lambertian{vec3(0.f)};
            m.emission = vec3(1.f / (radius[i] * radius[i]));
            test::add_icosphere(*scene, vec3(xs[i], 4.f, 0.f), radius[i], 1, test::add_material(*scene, m));
        }
        camera.eye = vec3(0.f, 2.f, 15.f);
        camera.target = vec3(0.f, 0.2f, 4.5f);
        camera.vfov_deg = 32.f;
        const vec3 light_line(0.f, 4.f, 0.f);
        const float zs[4] = {2.f, 3.6f, 5.2f, 6.8f};
        for (int j = 0; j < 4; ++j) {
            Material m;
            m.bsdf = Glossy{vec3(0.f), vec3(0.9f), kAlpha[j]};
            const uint32_t id = test::add_material(*scene, m);
            plate_material.push_back(id);
            // Tilted so the mirror direction links the camera and the line of lights.
            const vec3 c(0.f, 0.f, zs[j]);
            const vec3 n = glm::normalize(glm::normalize(camera.eye - c) + glm::normalize(light_line - c));
            const vec3 t = glm::normalize(glm::cross(vec3(1, 0, 0), n));  // in the y-z plane
            const vec3 hx(5.f, 0.f, 0.f), ht = 0.6f * t;
            test::add_quad(*scene, c - hx - ht, c + hx - ht, c + hx + ht, c - hx + ht, id);
        }
    }
    // Region of pixel (x, y): 4 * plate + quarter of the plate along x, or -1 when the pixel centre misses.
    std::vector<int> regions(int w, int h) const {
        const test::Tracer tracer(scene);
        const Camera cam(camera, w, h);
        std::vector<int> out(size_t(w) * h, -1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const Ray r = cam.generate(vec2(x + 0.5f, y + 0.5f), vec2(0.5f));
                Hit hit;
                if (!tracer.accel().intersect(r, hit)) continue;
                const uint32_t mid = scene->material_ids[hit.prim];
                for (int j = 0; j < 4; ++j)
                    if (plate_material[size_t(j)] == mid) {
                        const float px = r.o.x + hit.t * r.d.x;
                        out[size_t(y) * w + x] = 4 * j + std::clamp(int((px + 5.f) / 2.5f), 0, 3);
                    }
            }
        return out;
    }
};

TEST(AgreementVeach, RegionMeansAgreeAcrossEstimators) {
    const VeachScene v;
    const int w = 24, h = 15;
    const auto region = v.regions(w, h);
    for (int g = 0; g < 16; ++g) ASSERT_GT(std::count(region.begin(), region.end(), g), 2) << "region " << g;
    const auto bsdf =
        region_stats(render_stats(v.scene, v.camera, make_settings(false, false, true, 31), w, h, 2048), region, 16);
    const auto nee =
        region_stats(render_stats(v.scene, v.camera, make_settings(true, false, true, 32), w, h, 2048), region, 16);
    const auto mis =
        region_stats(render_stats(v.scene, v.camera, make_settings(true, true, true, 33), w, h, 1024), region, 16);
    const double family = 3.0 * 16 * 3;
    EXPECT_EQ(compare_regions(mis, bsdf, family), "") << "MIS vs BSDF-only";
    EXPECT_EQ(compare_regions(mis, nee, family), "") << "MIS vs NEE";
    EXPECT_EQ(compare_regions(nee, bsdf, family), "") << "NEE vs BSDF-only";
}

TEST(AgreementVeach, MisIsAtLeastAsGoodAsTheBetterStrategyPerPlate) {
    const VeachScene v;
    const int w = 32, h = 20, spp = 64, seeds = 8;
    const auto region = v.regions(w, h);
    double rel[3][4] = {};  // [method][plate]
    std::vector<double> ref(size_t(w) * h * 3, 0.0);
    std::vector<test::PixelStats> images[3];
    for (int s = 0; s < seeds; ++s)
        for (int m = 0; m < 3; ++m) {
            const bool nee = m != 1, mis = m == 2;
            images[m].push_back(
                render_stats(v.scene, v.camera, make_settings(nee, mis, true, 100 + 3 * s + m), w, h, spp));
            for (size_t i = 0; i < ref.size(); ++i) ref[i] += images[m].back().mean[i] / (3.0 * seeds);
        }
    for (int m = 0; m < 3; ++m)
        for (const test::PixelStats& st : images[m]) {
            double acc[4] = {}, cnt[4] = {};
            for (size_t i = 0; i < region.size(); ++i) {
                if (region[i] < 0) continue;
                const int plate = region[i] / 4;
                for (int c = 0; c < 3; ++c) {
                    acc[plate] += st.var_mean[i * 3 + c] / (ref[i * 3 + c] * ref[i * 3 + c] + 0.01);
                    cnt[plate] += 1.0;
                }
            }
            for (int j = 0; j < 4; ++j) rel[m][j] += acc[j] / cnt[j] / seeds;
        }
    for (int j = 0; j < 4; ++j) {
        const double best = std::min(rel[0][j], rel[1][j]);
        EXPECT_LE(rel[2][j], 1.1 * best) << "plate " << j << " (alpha " << VeachScene::kAlpha[j] << "): relMSE NEE "
                                         << rel[0][j] << ", BSDF " << rel[1][j] << ", MIS " << rel[2][j];
        std::printf("[ info ] Veach plate %d (alpha %.2f): relMSE NEE %.4g, BSDF %.4g, MIS %.4g\n", j,
                    double(VeachScene::kAlpha[j]), rel[0][j], rel[1][j], rel[2][j]);
    }
}

}  // namespace
}  // namespace pv
