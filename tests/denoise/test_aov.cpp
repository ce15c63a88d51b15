// tests/denoise/test_aov.cpp: AOVs (core/denoise/aov.h). First-hit features against geometry known in closed form (the
// Cornell box's back wall; a mirror and a glass interface in front of coloured walls, whose Fresnel split is checked
// against a binomial bound), the film's statistics layers against hand-computed sums, and the multi-layer EXR
// round trip with its error for a mis-sized layer.
// Test kinds: unit
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>

#include "core/base/error.h"
#include "core/denoise/aov.h"
#include "tests/support/scenes.h"

namespace pv {
namespace {

Ray make_ray(vec3 o, vec3 d) {
    Ray r;
    r.o = o;
    r.d = d;
    return r;
}

TEST(Aov, CornellBackWall) {
    const test::Tracer tracer(test::cornell_box());
    Sampler sampler(0, SamplerKind::Independent);
    sampler.start(uvec2(0), 0);
    // From the camera at the back wall (the plane z = 559.2 in Cornell's measurements) above the tall block.
    const vec3 eye(278.f, 273.f, -800.f), target(278.f, 450.f, 559.2f);
    const FeatureSample f = trace_features(tracer, make_ray(eye, glm::normalize(target - eye)), sampler);
    EXPECT_NEAR(f.depth, glm::length(target - eye), 0.05f);
    EXPECT_NEAR(f.normal.z, -1.f, 1e-4f);
    EXPECT_NEAR(f.albedo.x, 0.725f, 1e-6f);
    EXPECT_NEAR(f.albedo.y, 0.71f, 1e-6f);
    EXPECT_NEAR(f.albedo.z, 0.68f, 1e-6f);
    // A ray into the void has no features.
    const FeatureSample miss = trace_features(tracer, make_ray(eye, vec3(0.f, 0.f, -1.f)), sampler);
    EXPECT_EQ(miss.depth, 0.f);
    EXPECT_EQ(miss.albedo, vec3(0.f));
}

// A delta surface in the plane z = 0 facing +z, a red wall at z = 10 facing -z (behind the camera at z = 5) and a
// green wall at z = -5 facing +z.
std::shared_ptr<Scene> specular_scene(const Bsdf& middle) {
    auto scene = std::make_shared<Scene>();
    Material m;
    m.bsdf = middle;
    const uint32_t mid = test::add_material(*scene, m);
    m.bsdf = Lambertian{vec3(1.f, 0.f, 0.f)};
    const uint32_t red = test::add_material(*scene, m);
    m.bsdf = Lambertian{vec3(0.f, 1.f, 0.f)};
    const uint32_t green = test::add_material(*scene, m);
    const float s = 100.f;
    test::add_quad(*scene, {-s, -s, 0}, {s, -s, 0}, {s, s, 0}, {-s, s, 0}, mid);
    test::add_quad(*scene, {-s, -s, 10}, {-s, s, 10}, {s, s, 10}, {s, -s, 10}, red);
    test::add_quad(*scene, {-s, -s, -5}, {s, -s, -5}, {s, s, -5}, {-s, s, -5}, green);
    return scene;
}

TEST(Aov, MirrorFollowsTheChain) {
    const test::Tracer tracer(specular_scene(Mirror{vec3(0.5f)}));
    Sampler sampler(0, SamplerKind::Independent);
    sampler.start(uvec2(0), 0);
    const FeatureSample f = trace_features(tracer, make_ray(vec3(0.f, 0.f, 5.f), vec3(0.f, 0.f, -1.f)), sampler);
    EXPECT_NEAR(f.depth, 15.f, 1e-3f);     // 5 to the mirror, 10 back to the red wall
    EXPECT_NEAR(f.albedo.x, 0.5f, 1e-6f);  // red, tinted by the mirror's reflectance
    EXPECT_EQ(f.albedo.y, 0.f);
    EXPECT_NEAR(f.normal.z, -1.f, 1e-5f);  // the red wall's normal, facing the reflected ray
}

TEST(Aov, GlassSplitsByFresnel) {
    // Normal incidence on eta 1.5: reflection with F = ((1.5 - 1) / (1.5 + 1))^2 = 0.04 (red), refraction otherwise
    // (green, at depth 5 + 5). The mean red albedo over n samples is binomial: within 4 standard errors of F.
    const test::Tracer tracer(specular_scene(Dielectric{1.5f}));
    Sampler sampler(3, SamplerKind::Independent);
    const int n = 20000;
    double red = 0, green = 0;
    for (int i = 0; i < n; ++i) {
        sampler.start(uvec2(1, 2), uint32_t(i));
        const FeatureSample f = trace_features(tracer, make_ray(vec3(0.f, 0.f, 5.f), vec3(0.f, 0.f, -1.f)), sampler);
        red += f.albedo.x;
        green += f.albedo.y;
        if (f.albedo.y > 0.f) {
            EXPECT_NEAR(f.depth, 10.f, 1e-3f);
        }
    }
    const double F = 0.04, se = std::sqrt(F * (1 - F) / n);
    EXPECT_NEAR(red / n, F, 4 * se);
    EXPECT_NEAR(green / n, 1 - F, 4 * se);
}

TEST(Aov, RenderFeaturesMatchesSingleRays) {
    // The per-pixel means: every sample of a pixel that sees only the back wall has the same albedo and normal.
    const test::Tracer tracer(test::cornell_box());
    const int w = 16, h = 16;
    const FeatureImage img = render_features(tracer, Camera(test::cornell_box()->camera, w, h), w, h, 4, 0);
    ASSERT_EQ(img.albedo.size(), size_t(w * h));
    const size_t i = size_t(5) * w + 8;  // upper middle: back wall
    EXPECT_NEAR(img.albedo[i].x, 0.725f, 1e-5f);
    EXPECT_NEAR(img.normal[i].z, -1.f, 1e-4f);
    EXPECT_GT(img.depth[i], 1359.f);
}

// A raised cancel flag stops the feature pass before any row (the viewer drops such an image); a lowered one
// changes nothing.
TEST(Aov, RenderFeaturesStopsWhenCancelled) {
    const test::Tracer tracer(test::cornell_box());
    const int w = 16, h = 16;
    const Camera camera(test::cornell_box()->camera, w, h);
    std::atomic<bool> cancel{true};
    const FeatureImage stopped = render_features(tracer, camera, w, h, 4, 0, &cancel);
    ASSERT_EQ(stopped.albedo.size(), size_t(w * h));
    for (size_t i = 0; i < stopped.albedo.size(); ++i) {
        EXPECT_EQ(stopped.albedo[i], vec3(0.f)) << i;
        EXPECT_EQ(stopped.depth[i], 0.f) << i;
    }
    cancel = false;
    const FeatureImage full = render_features(tracer, camera, w, h, 4, 0, &cancel);
    const FeatureImage reference = render_features(tracer, camera, w, h, 4, 0);
    EXPECT_EQ(full.albedo, reference.albedo);
    EXPECT_EQ(full.normal, reference.normal);
    EXPECT_EQ(full.depth, reference.depth);
}

TEST(Aov, FilmLayers) {
    Film film(2, 1);
    // Pixel 0: samples 1, 3 (even) and 2, 6 (odd); pixel 1: one even sample.
    const float v[4] = {1.f, 2.f, 3.f, 6.f};
    for (uint32_t i = 0; i < 4; ++i) ASSERT_TRUE(film.add(0, 0, i, vec3(v[i])));
    ASSERT_TRUE(film.add(1, 0, 0, vec3(5.f)));
    const std::vector<ExrLayer> layers = film_layers(film);
    ASSERT_EQ(layers.size(), 4u);
    EXPECT_EQ(layers[0].channels[0], "SampleCount");
    EXPECT_EQ(layers[0].data, (std::vector<float>{4.f, 1.f}));
    // Sample variance of {1, 2, 3, 6} is 14/3; of the mean, 14/12.
    EXPECT_NEAR(layers[1].data[0], 14.f / 12.f, 1e-6f);
    EXPECT_EQ(layers[2].channels[0], "even.R");
    EXPECT_EQ(layers[2].data[0], 2.f);  // (1 + 3) / 2
    EXPECT_EQ(layers[3].data[0], 4.f);  // (2 + 6) / 2
    EXPECT_EQ(layers[2].data[3], 5.f);
    EXPECT_EQ(layers[3].data[3], 0.f);  // no odd sample
}

TEST(Aov, ExrLayersRoundTrip) {
    const std::string path = (std::filesystem::temp_directory_path() / "pathview_test_aov.exr").string();
    const int w = 3, h = 2;
    ExrLayer rgb{{"R", "G", "B"}, {}}, z{{"Z"}, {}};
    for (int i = 0; i < w * h * 3; ++i) rgb.data.push_back(float(i) * 0.25f);
    for (int i = 0; i < w * h; ++i) z.data.push_back(100.f + float(i));
    write_exr_layers(path, w, h, {rgb, z}, {{"pathview:test", "yes"}});
    int rw = 0, rh = 0;
    EXPECT_EQ(read_exr_layer(path, {"R", "G", "B"}, &rw, &rh).data, rgb.data);
    EXPECT_EQ(rw, w);
    EXPECT_EQ(rh, h);
    EXPECT_EQ(read_exr_layer(path, {"Z"}, &rw, &rh).data, z.data);
    Metadata meta;
    EXPECT_EQ(read_exr(path, &meta).rgb, rgb.data);  // the plain reader sees the main RGB
    EXPECT_EQ(meta["pathview:test"], "yes");
    try {
        read_exr_layer(path, {"Albedo.R"}, &rw, &rh);
        ADD_FAILURE() << "missing channel accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("Albedo.R"), std::string::npos);
    }
    z.data.pop_back();
    EXPECT_THROW(write_exr_layers(path, w, h, {rgb, z}), Error);
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace pv
