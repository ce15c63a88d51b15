// tests/load/test_real_scenes.cpp: what archive scenes need (issue 6): textures and their lookup, alpha cut-outs,
// environment maps (sampling chi-square, analytic irradiance), large meshes in bounded memory, MTL quirks.
// Bounds come from the sample variance with Sidak-corrected k (tests/support/stats.h); seeds are fixed.
// Test kinds: unit; statistical: EnvironmentMapSampling; analytic: EnvironmentIrradiance AlphaCutOut
// Test kinds: regression: MtlQuirks LoaderLimits; slow: LargeMeshSlow
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>

#include "core/base/error.h"
#include "core/frame/renderer.h"
#include "core/image/image_io.h"
#include "core/load/obj_loader.h"
#include "core/load/scene_file.h"
#include "core/sampling/warp.h"
#include "core/scene/environment.h"
#include "support/scenes.h"
#include "support/stats.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

using test::Moments;
using test::sidak_k;

// A fresh folder under the system temp dir, removed at the end of the test.
struct TempDir : test::TestDir {
    TempDir() : TestDir("pathview-test") {}
};

// A unit quad in the z = 0 plane, uv = xy, facing +z.
const char* kQuadObj =
    "mtllib quad.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "usemtl tex\nf 1/1 2/2 3/3 4/4\n";

// Radiance along a ray straight down onto (x, y) of the quad, BSDF-only, no roulette: with a constant unit
// environment and a convex scene, every sample equals the albedo exactly (zero variance).
vec3 radiance_at(const test::Tracer& tracer, float x, float y, uint32_t index) {
    RenderSettings s;
    s.light_sampling = false;
    s.russian_roulette = false;
    s.max_depth = 4;
    const ScopedFtzDaz ftz;  // the renderer's floating-point mode
    Sampler sampler(7);
    sampler.start(uvec2(1, 2), index);
    PathCounters c;
    Ray r;
    r.o = vec3(x, y, 1.f);
    r.d = vec3(0.f, 0.f, -1.f);
    return trace_path(tracer, s, r, sampler, c);
}

// Moments (per channel) of `spp` samples of the radiance along one fixed ray, direct light only (max depth 1,
// no roulette), with the independent sampler since the callers' bounds use the i.i.d. sample variance.
std::array<Moments, 3> radiance_moments(const test::Tracer& tracer, bool nee, bool mis, Ray ray, int spp,
                                        uint32_t seed) {
    RenderSettings s;
    s.light_sampling = nee;
    s.mis = mis;
    s.russian_roulette = false;
    s.max_depth = 1;
    const ScopedFtzDaz ftz;  // the renderer's floating-point mode
    std::array<Moments, 3> m;
    PathCounters c;
    Sampler sampler(seed, SamplerKind::Independent);
    for (int i = 0; i < spp; ++i) {
        sampler.start(uvec2(3, 4), uint32_t(i));
        const vec3 L = trace_path(tracer, s, ray, sampler, c);
        for (int ch = 0; ch < 3; ++ch) m[ch].add(L[ch]);
    }
    return m;
}

Ray ray_from(vec3 o, vec3 d) {
    Ray r;
    r.o = o;
    r.d = d;
    return r;
}

// A loaded scene's texels, the sky's included, end up in one region (pack_texels, once the scene is complete): each
// texture's storage 64-byte aligned right after the one before it. An OBJ lit by the default sky and a JSON scene
// naming the sky both.
TEST(Textures, LoadedScenesKeepTheirTexelsAndTheSkyInOneRegion) {
    TempDir dir;
    Image img(3, 5);  // 15 texels: 4x4 blocks of codes pad it to 2 blocks (128 bytes)
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 3; ++x) img.set(x, y, vec3(float(x) / 2.f, float(y) / 4.f, 0.5f));
    write_png((dir.path / "checker.png").string(), img);
    dir.write("quad.mtl", "newmtl tex\nKd 0.5 0.5 0.5\nmap_Kd checker.png\n");
    const std::string obj = dir.write("quad.obj", kQuadObj);
    const std::string json = dir.write("quad.json", R"({"obj": "quad.obj", "environment": {"map": "sky"}})");
    for (const std::string& path : {obj, json}) {
        const Scene scene = load_scene(path);
        ASSERT_EQ(scene.textures.size(), 2u) << path << ": the quad's texture and the sky";
        ASSERT_EQ(scene.environment_map, 1u) << path;
        const Texture& surface = scene.textures[0];
        const Texture& sky = scene.textures[1];
        ASSERT_GT(surface.bytes(), 0u);
        const auto at = [](const Texture& t) { return reinterpret_cast<uintptr_t>(t.storage()); };
        EXPECT_EQ(at(surface) % 64, 0u) << path;
        EXPECT_EQ(at(sky), at(surface) + (surface.bytes() + 63) / 64 * 64)
            << path << ": the sky right after the quad's texels";
    }
}

TEST(Textures, QuadShowsTheTexelUnderEachPoint) {
    TempDir dir;
    // 2x2 texture, row 0 at the top: (red, green / blue, white) in sRGB bytes 255 -> linear 1.
    Image img(2, 2);
    img.set(0, 0, vec3(1, 0, 0));
    img.set(1, 0, vec3(0, 1, 0));
    img.set(0, 1, vec3(0, 0, 1));
    img.set(1, 1, vec3(1, 1, 1));
    write_png((dir.path / "Checker.png").string(), img);
    dir.write("quad.mtl", "newmtl tex\nKd 0.5 0.5 0.5\nmap_Kd checker.PNG\n");  // wrong case on purpose
    auto scene = std::make_shared<Scene>(load_obj(dir.write("quad.obj", kQuadObj)));
    ASSERT_EQ(scene->textures.size(), 1u) << "the case-insensitive match should find Checker.png";
    scene->environment.background = vec3(1.f);
    const test::Tracer tracer(scene);
    // Texel centres: u = 0.25 / 0.75; v = 0.75 is the TOP row (OBJ v = 0 is the image's bottom).
    const struct {
        float x, y;
        vec3 expected;
    } cases[] = {{0.25f, 0.75f, vec3(1, 0, 0)},
                 {0.75f, 0.75f, vec3(0, 1, 0)},
                 {0.25f, 0.25f, vec3(0, 0, 1)},
                 {0.75f, 0.25f, vec3(1, 1, 1)}};
    for (const auto& c : cases)
        for (uint32_t i = 0; i < 16; ++i) {
            const vec3 L = radiance_at(tracer, c.x, c.y, i);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(L[k], c.expected[k], 1e-5f) << "at " << c.x << "," << c.y;
        }
    // Between texel centres the lookup is bilinear: halfway between red and green.
    const vec3 mid = radiance_at(tracer, 0.5f, 0.75f, 0);
    EXPECT_NEAR(mid.x, 0.5f, 1e-5f);
    EXPECT_NEAR(mid.y, 0.5f, 1e-5f);
}

TEST(Textures, MissingTextureWarnsOnceAndKeepsTheFlatColour) {
    TempDir dir;
    dir.write("quad.mtl", "newmtl tex\nKd 0.25 0.5 0.75\nmap_Kd nowhere.png\n");
    auto scene = std::make_shared<Scene>(load_obj(dir.write("quad.obj", kQuadObj)));
    size_t warnings = 0;
    for (const auto& w : scene->warnings) warnings += w.find("nowhere.png") != std::string::npos;
    EXPECT_EQ(warnings, 1u);
    EXPECT_EQ(scene->materials[0].base_color_texture, kNoIndex);
    scene->environment.background = vec3(1.f);
    const test::Tracer tracer(scene);
    const vec3 L = radiance_at(tracer, 0.3f, 0.6f, 0);
    EXPECT_NEAR(L.x, 0.25f, 1e-5f);
    EXPECT_NEAR(L.y, 0.5f, 1e-5f);
    EXPECT_NEAR(L.z, 0.75f, 1e-5f);
}

// A black occluder with opacity `alpha` (a 1x1 map_d) between a receiver and a white sky: the receiver's
// radiance is (1 - alpha * covered) where `covered` is the fraction of cosine-weighted sky the occluder spans.
// Exercises bounce rays (BSDF sampling) and shadow rays (light sampling) through the cut-out.
TEST(AlphaCutOut, AlphaCutOutPassesLightInProportion) {
    TempDir dir;
    const float alpha = 0.3f;
    // map_d without an alpha channel uses the raw grey byte. write_png applies the sRGB curve, so hand it the
    // linear value whose sRGB byte is round(alpha * 255).
    const float byte_value = std::round(alpha * 255.f) / 255.f;
    const float lin = byte_value <= 0.04045f ? byte_value / 12.92f : std::pow((byte_value + 0.055f) / 1.055f, 2.4f);
    Image mask(1, 1);
    mask.set(0, 0, vec3(lin));
    write_png((dir.path / "mask.png").string(), mask);
    const float a = byte_value;  // the opacity the loader will read
    dir.write("scene.mtl", "newmtl occluder\nKd 0 0 0\nmap_d mask.png\nnewmtl receiver\nKd 1 1 1\n");
    const float half = 500.f, h = 1.f;
    const std::string obj =
        "mtllib scene.mtl\n"
        "v -500 -500 1\nv 500 -500 1\nv 500 500 1\nv -500 500 1\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
        "usemtl occluder\nf 1/1 2/2 3/3 4/4\nusemtl receiver\nf 5 6 7 8\n";
    auto scene = std::make_shared<Scene>(load_obj(dir.write("scene.obj", obj)));
    ASSERT_NE(scene->materials[0].alpha_texture, kNoIndex);
    scene->environment.background = vec3(1.f);
    const test::Tracer tracer(scene);
    // Cosine-weighted fraction of the hemisphere inside the occluder, seen from the receiver's centre: the
    // occluder is a square, so integrate numerically (midpoint rule on a fine grid of its area).
    double covered = 0.0;
    const int n = 2000;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double x = -half + (i + 0.5) * 2 * half / n, y = -half + (j + 0.5) * 2 * half / n;
            const double d2 = x * x + y * y + h * h;
            covered += (h * h) / (d2 * d2) * (2 * half / n) * (2 * half / n) / M_PI;  // cos_r cos_o / (pi d^2) dA
        }
    const double expected = 1.0 - a * covered;

    const int spp = 4096;
    const double k = sidak_k(2);
    for (const bool nee : {false, true}) {
        const Moments m = radiance_moments(tracer, nee, false, ray_from(vec3(0, 0, 0.5f), vec3(0, 0, -1)), spp, 11)[0];
        EXPECT_LE(std::fabs(m.mean - expected), k * m.stderr_of_mean())
            << (nee ? "shadow rays" : "bounce rays") << ": mean " << m.mean << " expected " << expected;
    }
}

// An environment map made of a few bright and dark texels, so both the sampling and the lookup are non-trivial.
std::shared_ptr<Scene> scene_with_map(int w, int h, float rotation_deg) {
    auto scene = std::make_shared<Scene>();
    std::vector<vec4> texels(size_t(w) * size_t(h));
    Pcg32 rng(5, 9);
    for (auto& t : texels) {
        const float r = rng.next_float();
        t = vec4(r < 0.1f ? 40.f * rng.next_float() : 0.2f * rng.next_float(), rng.next_float(), 0.5f, 1.f);
    }
    texels[3] = vec4(0.f, 0.f, 0.f, 1.f);  // a black texel is never sampled
    scene->textures.emplace_back(w, h, std::move(texels));
    scene->environment_map = 0;
    scene->environment.rotation_deg = rotation_deg;
    return scene;
}

TEST(Environment, UvDirectionRoundTrip) {
    auto scene = scene_with_map(16, 8, 30.f);
    const Environment env(*scene);
    Pcg32 rng(1, 2);
    for (int i = 0; i < 1000; ++i) {
        const vec2 uv(rng.next_float(), 0.001f + 0.998f * rng.next_float());
        const vec2 back = env.direction_to_uv(env.uv_to_direction(uv));
        EXPECT_NEAR(std::fmod(back.x - uv.x + 1.5f, 1.f) - 0.5f, 0.f, 1e-4f);
        EXPECT_NEAR(back.y, uv.y, 1e-4f);
    }
}

// Mitsuba-style chi-square goodness of fit on the sphere: equal-area cells in (phi, cos theta), expected counts by
// integrating pdf() over each cell on a sub-grid, cells with expected < 5 pooled, Sidak over the maps tested.
// Not tests/support/chi2.h: a lat-long map's solid-angle pdf has an integrable 1/sin(theta) singularity at the
// poles, which that harness's adaptive Simpson (evaluating on cell edges) chases without end; the midpoint rule on
// a fine sub-grid never evaluates at the pole and converges.
TEST(EnvironmentMapSampling, SamplingMatchesPdfChiSquare) {
    const int maps = 2;
    for (int t = 0; t < maps; ++t) {
        auto scene = scene_with_map(t == 0 ? 16 : 7, t == 0 ? 8 : 5, t == 0 ? 0.f : 77.f);
        const Environment env(*scene);
        const int nphi = 64, ncos = 32, sub = 40;  // fine sub-grid: the pdf jumps at texel edges
        const size_t n = 1000000;
        std::vector<double> observed(size_t(nphi) * ncos, 0.0), expected(observed.size(), 0.0);
        auto cell = [&](vec3 d) {
            float phi = std::atan2(d.y, d.x);
            if (phi < 0) phi += 2 * kPi;
            const int i = std::min(int(phi / (2 * kPi) * nphi), nphi - 1);
            const int j = std::min(int((1.f - d.z) * 0.5f * ncos), ncos - 1);
            return size_t(j) * nphi + i;
        };
        Pcg32 rng(3, uint64_t(t));
        size_t failed = 0, mismatched = 0;
        for (size_t s = 0; s < n; ++s) {
            const vec2 u(rng.next_float(), rng.next_float());
            auto es = env.sample(u);
            if (!es) {
                ++failed;
                continue;
            }
            ASSERT_GT(es->pdf, 0.f);
            // sample() and pdf() agree except where float rounding moves a direction across a texel edge.
            if (std::fabs(es->pdf - env.pdf(es->wi)) > 1e-3f * es->pdf) ++mismatched;
            observed[cell(es->wi)] += 1.0;
        }
        EXPECT_LT(double(failed), 1e-4 * double(n));
        EXPECT_LT(double(mismatched), 1e-4 * double(n)) << "sample().pdf != pdf(wi) too often";
        // Integrate pdf over each cell: d omega = d phi d cos theta.
        const double dphi = 2 * M_PI / nphi, dcos = 2.0 / ncos;
        double total = 0.0;
        for (int j = 0; j < ncos; ++j)
            for (int i = 0; i < nphi; ++i) {
                double acc = 0.0;
                for (int a = 0; a < sub; ++a)
                    for (int b = 0; b < sub; ++b) {
                        const double phi = (i + (a + 0.5) / sub) * dphi;
                        const double z = 1.0 - (j + (b + 0.5) / sub) * dcos;
                        const double r = std::sqrt(std::max(0.0, 1 - z * z));
                        acc += env.pdf(vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
                    }
                expected[size_t(j) * nphi + i] = acc / (sub * sub) * dphi * dcos * double(n);
                total += expected[size_t(j) * nphi + i];
            }
        EXPECT_NEAR(total / double(n), 1.0, 0.02) << "pdf integrates to " << total / double(n);
        // Pool cells, smallest expectation first, until each pooled term expects at least 5.
        std::vector<size_t> order(observed.size());
        for (size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
        double chi2 = 0.0, pool_e = 0.0, pool_o = 0.0;
        int terms = 0;
        for (size_t idx : order) {
            if (expected[idx] == 0.0) {
                EXPECT_EQ(observed[idx], 0.0) << "a sample landed where pdf = 0";
                continue;
            }
            pool_e += expected[idx];
            pool_o += observed[idx];
            if (pool_e >= 5.0) {
                chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
                ++terms;
                pool_e = pool_o = 0.0;
            }
        }
        if (pool_e > 0.0) {
            chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
            ++terms;
        }
        const double p = test::chi2_p_value(chi2, terms - 1);
        EXPECT_GT(p, test::sidak_alpha(0.01, maps)) << "map " << t << ": chi2 " << chi2 << " dof " << terms - 1;
    }
}

// A white diffuse plane under a non-uniform map: its radiance is (1/pi) * E with E = integral of L cos over the
// upper hemisphere, which for a per-texel-constant map is an exact sum over texels. NEE-only, BSDF-only and MIS
// must all converge to it.
TEST(EnvironmentIrradiance, DiffusePlaneUnderMapMatchesAnalyticIrradiance) {
    auto scene = scene_with_map(16, 8, 40.f);
    const uint32_t white = test::add_material(*scene, Material{"white", Lambertian{vec3(1.f)}});
    // Large horizontal plane facing +y (environment's up).
    test::add_quad(*scene, vec3(-1e3f, 0, 1e3f), vec3(1e3f, 0, 1e3f), vec3(1e3f, 0, -1e3f), vec3(-1e3f, 0, -1e3f),
                   white);
    const Environment env(*scene);
    // Exact irradiance: each texel row spans [theta0, theta1], each column d phi; L constant per texel.
    const Texture& map = scene->textures[0];
    double E[3] = {0, 0, 0};
    for (int y = 0; y < map.height() / 2; ++y)  // the upper hemisphere (8 rows: exactly rows 0..3)
        for (int x = 0; x < map.width(); ++x) {
            const double t0 = M_PI * y / map.height(), t1 = M_PI * (y + 1) / map.height();
            const double dphi = 2 * M_PI / map.width();
            const vec4 L = map.lookup(vec2((x + 0.5f) / map.width(), 1.f - (y + 0.5f) / map.height()));
            const double w = dphi * 0.5 * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0));
            for (int c = 0; c < 3; ++c) E[c] += L[c] * w;
        }
    const test::Tracer tracer(scene);
    const int spp = 20000;
    const double k = sidak_k(9);
    struct Mode {
        bool nee, mis;
        const char* name;
    } modes[] = {{false, false, "bsdf"}, {true, false, "nee"}, {true, true, "mis"}};
    for (const Mode& mode : modes) {
        const auto m =
            radiance_moments(tracer, mode.nee, mode.mis, ray_from(vec3(0.3f, 1, -0.2f), vec3(0, -1, 0)), spp, 21);
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_LE(std::fabs(m[ch].mean - E[ch] / M_PI), k * m[ch].stderr_of_mean() + 1e-7)
                << mode.name << " channel " << ch << ": " << m[ch].mean << " vs " << E[ch] / M_PI;
    }
}

// A sun (a cap of uniform radiance, angular radius a) over a white diffuse plane, sun at theta from the normal and
// fully above the horizon: E = pi L sin^2(a) cos(theta) = irradiance * cos(theta) exactly (the closed-form irradiance
// of a polygonal or spherical light, the sphere case), so the plane's radiance is irradiance * cos(theta) / pi. With
// and without a sky under it.
TEST(EnvironmentIrradiance, SunOnDiffusePlaneMatchesClosedForm) {
    const float theta = glm::radians(40.f);
    const int spp = 20000;
    const double k = sidak_k(12);
    for (const float sky : {0.f, 0.5f}) {
        auto scene = std::make_shared<Scene>();
        const uint32_t white = test::add_material(*scene, Material{"white", Lambertian{vec3(1.f)}});
        test::add_quad(*scene, vec3(-1e3f, 0, 1e3f), vec3(1e3f, 0, 1e3f), vec3(1e3f, 0, -1e3f), vec3(-1e3f, 0, -1e3f),
                       white);
        scene->environment.sun_direction = vec3(std::sin(theta), std::cos(theta), 0.f);
        scene->environment.sun_angular_radius_deg = 5.f;  // wide enough that BSDF sampling alone finds it
        scene->environment.sun_irradiance = vec3(2.f, 1.f, 0.5f);
        scene->environment.background = vec3(sky);
        const test::Tracer tracer(scene);
        const struct {
            bool nee, mis;
            const char* name;
        } modes[] = {{false, false, "bsdf"}, {true, false, "nee"}, {true, true, "mis"}};
        for (const auto& mode : modes) {
            const Moments m =
                radiance_moments(tracer, mode.nee, mode.mis, ray_from(vec3(0.1f, 1, 0.2f), vec3(0, -1, 0)), spp, 32)[0];
            const double expected = 2.0 * std::cos(theta) / M_PI + sky;  // sun + the sky's upper hemisphere
            EXPECT_LE(std::fabs(m.mean - expected), k * m.stderr_of_mean())
                << mode.name << " sky " << sky << ": " << m.mean << " vs " << expected;
        }
    }
}

// The viewer asks environment_emits() on every Light edit instead of building sampling tables: it must agree.
TEST(Environment, EmitsAgreesWithTheFullEnvironment) {
    auto mapped = scene_with_map(8, 4, 0.f);
    Scene plain;
    for (const Scene* scene : {mapped.get(), &plain})
        for (const float strength : {0.f, 1.f})
            for (const vec3 sky : {vec3(0.f), vec3(0.2f)})
                for (const vec3 sun : {vec3(0.f), vec3(3.f)}) {
                    EnvironmentSettings s = scene->environment;
                    s.strength = strength;
                    s.background = sky;
                    s.sun_irradiance = sun;
                    EXPECT_EQ(environment_emits(*scene, s), !Environment(*scene, s).is_black())
                        << "map " << (scene == mapped.get()) << " strength " << strength << " sky " << sky.x << " sun "
                        << sun.x;
                }
}

TEST(Environment, UnlitSceneGetsTheDefaultSkyAndSaysSo) {
    TempDir dir;
    const std::string obj = dir.write("plane.obj", "v 0 0 0\nv 1 0 0\nv 1 0 1\nf 1 3 2\n");
    const Scene scene = load_scene(obj);
    EXPECT_NE(scene.environment_map, kNoIndex);
    size_t said = 0;
    for (const auto& w : scene.warnings) said += w.find("default sky") != std::string::npos;
    EXPECT_EQ(said, 1u);
    ASSERT_TRUE(scene.default_sky_warning.has_value());
    EXPECT_NE(scene.warnings[*scene.default_sky_warning].find("default sky"), std::string::npos);
    // A scene file that sets its background keeps it.
    dir.write("s.json", R"({"obj": "plane.obj", "background": [0.1, 0.2, 0.3]})");
    const Scene lit = load_scene((dir.path / "s.json").string());
    EXPECT_EQ(lit.environment_map, kNoIndex);
    EXPECT_FLOAT_EQ(lit.environment.background.y, 0.2f);
}

TEST(MtlQuirks, DocumentedBehaviour) {
    std::vector<std::string> w;
    // Ka is ambient, not emission.
    Material m = material_from_mtl("ka", vec3(0.5f), vec3(0.f), vec3(0.f), 10.f, 1.f, 1.f, 2, w);
    EXPECT_FALSE(m.has_emission());
    // d < 1 without Ni is opaque (warned); with Ni it is glass.
    w.clear();
    m = material_from_mtl("d", vec3(0.5f), vec3(0.f), vec3(0.f), 10.f, 1.f, 0.5f, 2, w);
    EXPECT_TRUE(std::holds_alternative<Lambertian>(m.bsdf));
    EXPECT_EQ(w.size(), 1u);
    m = material_from_mtl("glass", vec3(0.f), vec3(0.f), vec3(0.f), 10.f, 1.33f, 0.5f, 2, w);
    ASSERT_TRUE(std::holds_alternative<Dielectric>(m.bsdf));
    EXPECT_FLOAT_EQ(std::get<Dielectric>(m.bsdf).eta, 1.33f);
    // illum 3 without Ks: a perfect mirror.
    m = material_from_mtl("mirror", vec3(0.5f), vec3(0.f), vec3(0.f), 10.f, 1.f, 1.f, 3, w);
    ASSERT_TRUE(std::holds_alternative<Mirror>(m.bsdf));
    EXPECT_FLOAT_EQ(std::get<Mirror>(m.bsdf).reflectance.x, 1.f);
    // Ns over its whole range maps into [kMinAlpha, 1]; Kd + Ks > 1 is scaled to conserve energy.
    for (float ns : {-5.f, 0.f, 1.f, 10.f, 1000.f, 1e6f, 1e30f}) {
        m = material_from_mtl("ns", vec3(0.9f), vec3(0.5f), vec3(0.f), ns, 1.f, 1.f, 2, w);
        ASSERT_TRUE(std::holds_alternative<Glossy>(m.bsdf));
        const Glossy& g = std::get<Glossy>(m.bsdf);
        EXPECT_GE(g.alpha, kMinAlpha);
        EXPECT_LE(g.alpha, 1.f);
        EXPECT_LE(max_component(g.diffuse + g.specular), 1.f + 1e-6f);
    }
}

TEST(MtlQuirks, InfiniteKeEmitsNothingAndSaysSo) {
    std::vector<std::string> w;
    const Material m = material_from_mtl("hot", vec3(0.5f), vec3(0.f), vec3(INFINITY, 1.f, 1.f), 10.f, 1.f, 1.f, 2, w);
    EXPECT_FALSE(m.has_emission());
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("Ke is not finite"), std::string::npos);
}

TEST(LoaderLimits, TrianglesWhoseAreaOverflowsAreDroppedAsSuch) {
    // Edges of 1e17: the cross product's length overflows float, though every vertex is valid (< 1e18).
    const Scene s = load_obj_from_string("v 0 0 0\nv 1e17 0 0\nv 0 1e17 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n", "big.obj");
    EXPECT_EQ(s.stats.dropped_overflow, 1u);
    EXPECT_EQ(s.stats.dropped_degenerate, 0u);
    EXPECT_EQ(s.triangle_count(), 1u);
    size_t said = 0;
    for (const auto& x : s.warnings) said += x.find("area overflows") != std::string::npos;
    EXPECT_EQ(said, 1u);
}

TEST(MtlQuirks, BothDAndTrFoldIntoOneWarning) {
    TempDir dir;
    std::string mtl;
    for (int i = 0; i < 12; ++i) mtl += "newmtl m" + std::to_string(i) + "\nKd 0.5 0.5 0.5\nd 1\nTr 0\n";
    dir.write("q.mtl", mtl);
    const Scene s = load_obj(dir.write("q.obj", "mtllib q.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl m3\nf 1 2 3\n"));
    size_t dtr = 0;
    for (const auto& x : s.warnings) dtr += x.find("both d and Tr") != std::string::npos;
    EXPECT_EQ(dtr, 1u);
}

// A generated 2M-triangle grid: loads, and scene + BVH memory per triangle stays within a bound taken from the
// measured layout (positions 12 B/vertex ~ 6 B/tri, indices 12, material id 4; Embree's copy of vertices and
// indices ~ 18 B/tri plus a MEDIUM-quality BVH measured at ~85 B/tri: PLATFORM-NOTES).
TEST(LargeMeshSlow, TwoMillionTrianglesInBoundedMemory) {
    TempDir dir;
    const int n = 1000;  // n x n quads = 2n^2 triangles
    std::string obj;
    obj.reserve(size_t(n + 1) * (n + 1) * 24 + size_t(n) * n * 40);
    char buf[96];
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            std::snprintf(buf, sizeof buf, "v %d %.3f %d\n", i, 0.01 * std::sin(i * 0.1) * std::cos(j * 0.1), j);
            obj += buf;
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1;
            std::snprintf(buf, sizeof buf, "f %d %d %d %d\n", a, a + 1, a + n + 2, a + n + 1);
            obj += buf;
        }
    const std::string path = dir.write("grid.obj", obj);
    obj.clear();
    obj.shrink_to_fit();
    auto scene = std::make_shared<Scene>(load_obj(path));
    ASSERT_EQ(scene->triangle_count(), size_t(2) * n * n);
    const Accel accel(*scene);
    const double scene_bytes = double(scene->positions.size() * sizeof(vec3) + scene->triangles.size() * sizeof(uvec3) +
                                      scene->material_ids.size() * sizeof(uint32_t));
    const double per_tri = (scene_bytes + double(accel.stats().bytes)) / double(scene->triangle_count());
    RecordProperty("bytes_per_triangle", std::to_string(per_tri));
    std::printf("[ measured ] %.1f bytes per triangle (scene %.1f + BVH %.1f), BVH build %.3f s\n", per_tri,
                scene_bytes / double(scene->triangle_count()),
                double(accel.stats().bytes) / double(scene->triangle_count()), accel.stats().build_seconds);
    EXPECT_GT(accel.stats().bytes, 0u);
    EXPECT_LT(per_tri, 160.0);
}

}  // namespace
}  // namespace pv

namespace pv {
namespace {

TEST(Bookmarks, SavedWithTheSceneFileAndReloaded) {
    TempDir dir;
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
    const std::string json_path = dir.write("s.json", R"({"obj": "tri.obj", "background": [0.5, 0.5, 0.5]})");
    CameraDesc a;
    a.eye = vec3(1, 2, 3);
    a.target = vec3(0.5f, 0.5f, 0.f);
    a.vfov_deg = 33.f;
    a.aperture = 0.01f;
    EXPECT_EQ(save_bookmark(json_path, "front", a), json_path);
    CameraDesc b = a;
    b.eye = vec3(-4, 5, 6);
    save_bookmark(json_path, "side", b);
    b.vfov_deg = 50.f;
    save_bookmark(json_path, "side", b);  // replaces, does not duplicate
    const Scene s = load_scene(json_path);
    ASSERT_EQ(s.bookmarks.size(), 2u);
    EXPECT_FLOAT_EQ(s.environment.background.x, 0.5f);  // the file's other keys survive
    const CameraDesc& front = find_bookmark(s, "front");
    EXPECT_EQ(front.eye, a.eye);
    EXPECT_FLOAT_EQ(front.vfov_deg, 33.f);
    EXPECT_FLOAT_EQ(front.aperture, 0.01f);
    EXPECT_FLOAT_EQ(find_bookmark(s, "side").vfov_deg, 50.f);
    EXPECT_THROW(find_bookmark(s, "missing"), Error);
    // An OBJ alone gets a scene file next to it, which loads the same OBJ.
    const std::string obj = (dir.path / "tri.obj").string();
    const std::string sidecar = save_bookmark(obj, "top", a);
    EXPECT_EQ(sidecar, obj + ".json");
    const Scene t = load_scene(sidecar);
    EXPECT_EQ(t.triangle_count(), 1u);
    EXPECT_EQ(find_bookmark(t, "top").eye, a.eye);
    // No temporary file is left behind.
    for (const auto& e : std::filesystem::directory_iterator(dir.path))
        EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

}  // namespace
}  // namespace pv
