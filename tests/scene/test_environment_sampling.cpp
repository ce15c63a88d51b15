// tests/scene/test_environment_sampling.cpp: the alias tables behind Distribution1D/2D (exact slot arithmetic on a fine
// grid of uniforms, chi-square of samples against pdf()), and the environment map's texel search (approximate atan2
// within its bound, agreement with the libm texel away from edges, pdf proportional to eval per texel, uv-space
// chi-square for odd maps: all-zero rows, one bright texel, 1 x N and N x 1). Seeds are fixed; chi-square levels
// are Sidak-corrected over the cases of each test.
// Test kinds: unit; statistical: Distribution1D Distribution2D EnvironmentSampling
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "core/sampling/distribution.h"
#include "core/sampling/rng.h"
#include "core/scene/environment.h"
#include "support/stats.h"

namespace pv {
namespace {

// Pearson's statistic with cells pooled (smallest expectation first) until each pooled term expects >= 5; returns
// the p-value, or 0 with *why set when more than max_strays samples land where nothing is expected (a sample a
// float rounding away from its texel's edge may be binned across it).
double pooled_chi2_p(const std::vector<double>& observed, const std::vector<double>& expected, std::string* why,
                     double max_strays = 0.0) {
    std::vector<size_t> order(observed.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double chi2 = 0.0, pool_e = 0.0, pool_o = 0.0, strays = 0.0;
    int terms = 0;
    for (const size_t i : order) {
        if (expected[i] <= 0.0) {
            strays += observed[i];
            if (strays > max_strays) {
                *why = "cell " + std::to_string(i) + " has " + std::to_string(observed[i]) + " samples, expects 0";
                return 0.0;
            }
            continue;
        }
        pool_e += expected[i];
        pool_o += observed[i];
        if (pool_e >= 5.0) {
            chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
            pool_e = pool_o = 0.0;
            ++terms;
        }
    }
    if (pool_e > 0.0) {
        chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        ++terms;
    }
    *why = "chi2 " + std::to_string(chi2) + " dof " + std::to_string(terms - 1);
    return terms > 1 ? test::chi2_p_value(chi2, terms - 1) : 1.0;
}

// Weights with zeros, a dominant cell and a spread of small ones.
std::vector<float> random_weights(size_t n, uint64_t seed) {
    Pcg32 rng(seed, 17);
    std::vector<float> w(n);
    for (float& v : w) {
        const float r = rng.next_float();
        v = r < 0.2f ? 0.f : r < 0.25f ? 50.f * rng.next_float() : rng.next_float();
    }
    return w;
}

// The 1D cases: random, one nonzero cell, a single cell, uniform, and one tiny cell among large ones.
std::vector<std::vector<float>> weight_cases() {
    std::vector<float> one_hot(37, 0.f);
    one_hot[11] = 3.f;
    std::vector<float> tiny(50, 1.f);
    tiny[7] = 1e-7f;
    return {random_weights(5, 1),
            random_weights(64, 2),
            random_weights(1000, 3),
            one_hot,
            {2.f},
            std::vector<float>(9, 1.f),
            tiny};
}

// Every uniform on a grid of M = 4096 n midpoints goes through the table: each cell receives its weight's share of
// M up to one grid point per slot edge that bounds it (the slots that name it), and never a zero-weight cell.
TEST(AliasTable, ThresholdsReproduceTheWeightsOnAFineGrid) {
    for (const std::vector<float>& w : weight_cases()) {
        const size_t n = w.size(), m = 4096 * n;
        std::vector<AliasSlot> table(n);
        build_alias_table(w.data(), n, table.data());
        std::vector<double> count(n, 0.0), slots_naming(n, 1.0);
        for (const AliasSlot& s : table) {
            ASSERT_LT(s.alias, n);
            ASSERT_TRUE(s.q >= 0.f && s.q <= 1.f) << s.q;
            slots_naming[s.alias] += 1.0;
        }
        for (size_t k = 0; k < m; ++k) {
            float offset = -1.f;
            const size_t cell = sample_alias_table(table.data(), n, float((double(k) + 0.5) / double(m)), &offset);
            ASSERT_LT(cell, n);
            ASSERT_TRUE(offset >= 0.f && offset < 1.f) << offset;
            count[cell] += 1.0;
        }
        const double sum = std::accumulate(w.begin(), w.end(), 0.0);
        for (size_t i = 0; i < n; ++i) {
            if (w[i] == 0.f) {
                EXPECT_EQ(count[i], 0.0) << "n " << n << ": zero-weight cell " << i << " chosen";
            }
            EXPECT_LE(std::fabs(count[i] - double(w[i]) / sum * double(m)), 2.0 * slots_naming[i])
                << "n " << n << " cell " << i;
        }
    }
}

// Samples of x, histogrammed on 4 sub-cells per cell, against the piecewise-constant pdf; sample()'s pdf and cell
// agree with pdf(x) and floor(n x). x within float rounding of a cell edge may be binned across it (once per 1e5).
TEST(Distribution1D, AliasSamplingMatchesPdfChiSquare) {
    const auto cases = weight_cases();
    for (size_t c = 0; c < cases.size(); ++c) {
        const Distribution1D dist(cases[c]);
        const size_t n = dist.size(), bins = 4 * n, samples = 200000;
        std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
        for (size_t b = 0; b < bins; ++b) expected[b] = double(dist.pdf_cell(b / 4)) / double(bins) * samples;
        Pcg32 rng(7, c);
        size_t mismatched = 0;
        for (size_t s = 0; s < samples; ++s) {
            float pdf = 0.f;
            size_t cell = n;
            const float x = dist.sample(rng.next_float(), &pdf, &cell);
            ASSERT_TRUE(x >= 0.f && x < 1.f) << x;
            ASSERT_GT(pdf, 0.f);
            mismatched += pdf != dist.pdf(x) || cell != std::min(size_t(x * float(n)), n - 1);
            observed[std::min(size_t(double(x) * double(bins)), bins - 1)] += 1.0;
        }
        EXPECT_LE(mismatched, samples / 100000) << "n " << n;
        std::string why;
        EXPECT_GT(pooled_chi2_p(observed, expected, &why, double(samples) / 100000),
                  test::sidak_alpha(0.01, double(cases.size())))
            << "n " << n << ": " << why;
    }
    EXPECT_EQ(Distribution1D(std::vector<float>(4, 0.f)).integral(), 0.f);
    EXPECT_EQ(Distribution1D(std::vector<float>(4, 0.f)).pdf(0.3f), 1.f) << "all-zero weights become uniform";
}

struct Map {
    std::vector<float> f;
    int w, h;
    const char* name;
};

// 2D cases: random with two all-zero rows and an all-zero column, a single bright texel, 1 x N, N x 1.
std::vector<Map> map_cases() {
    std::vector<Map> maps;
    Map a{random_weights(13 * 9, 4), 13, 9, "13x9 with zero rows and column"};
    for (int x = 0; x < a.w; ++x) a.f[size_t(2 * a.w + x)] = a.f[size_t(6 * a.w + x)] = 0.f;
    for (int y = 0; y < a.h; ++y) a.f[size_t(y * a.w + 5)] = 0.f;
    maps.push_back(a);
    Map b{std::vector<float>(64, 0.f), 8, 8, "one bright texel"};
    b.f[8 * 5 + 3] = 10.f;
    maps.push_back(b);
    maps.push_back({random_weights(17, 5), 1, 17, "1x17"});
    maps.push_back({random_weights(17, 6), 17, 1, "17x1"});
    return maps;
}

// Samples on 3 x 3 sub-cells per texel against the joint pdf; sample()'s pdf and texel agree with pdf(p).
TEST(Distribution2D, AliasSamplingMatchesPdfChiSquare) {
    const auto maps = map_cases();
    for (size_t c = 0; c < maps.size(); ++c) {
        const Map& m = maps[c];
        const Distribution2D dist(m.f, m.w, m.h);
        const int bw = 3 * m.w, bh = 3 * m.h;
        const size_t samples = 200000;
        std::vector<double> observed(size_t(bw) * size_t(bh), 0.0), expected(observed.size(), 0.0);
        for (int y = 0; y < bh; ++y)
            for (int x = 0; x < bw; ++x)
                expected[size_t(y) * bw + x] =
                    double(dist.pdf_cell(size_t(y / 3) * m.w + size_t(x / 3))) / (double(bw) * double(bh)) * samples;
        Pcg32 rng(9, c);
        size_t mismatched = 0;
        for (size_t s = 0; s < samples; ++s) {
            float pdf = 0.f;
            size_t texel = 0;
            const vec2 p = dist.sample(vec2(rng.next_float(), rng.next_float()), &pdf, &texel);
            ASSERT_TRUE(p.x >= 0.f && p.x < 1.f && p.y >= 0.f && p.y < 1.f);
            ASSERT_GT(pdf, 0.f) << m.name;
            ASSERT_EQ(pdf, dist.pdf_cell(texel));
            mismatched += pdf != dist.pdf(p);
            const int bx = std::min(int(double(p.x) * bw), bw - 1), by = std::min(int(double(p.y) * bh), bh - 1);
            observed[size_t(by) * bw + bx] += 1.0;
        }
        EXPECT_LE(mismatched, samples / 100000) << m.name;
        std::string why;
        EXPECT_GT(pooled_chi2_p(observed, expected, &why, double(samples) / 100000),
                  test::sidak_alpha(0.01, double(maps.size())))
            << m.name << ": " << why;
    }
}

// The approximate atan2 behind the texel search stays within the error bound the search's margins assume.
TEST(EnvironmentTexels, ApproximateAtan2StaysWithinItsBound) {
    double worst = 0.0;
    const int steps = 2000000;
    for (int i = 0; i <= steps; ++i) {
        const double a = -M_PI + 2.0 * M_PI * i / steps;
        for (const double r : {1.0, 1e-20, 3e7}) {
            const float x = float(r * std::cos(a)), y = float(r * std::sin(a));
            double e = std::fabs(double(environment_atan2_approx(y, x)) - std::atan2(double(y), double(x)));
            e = std::min(e, 2.0 * M_PI - e);  // -pi and pi are the same direction
            worst = std::max(worst, e);
        }
    }
    EXPECT_LE(worst, 0.5 * double(environment_atan2_max_error())) << "measured max error " << worst;
    EXPECT_EQ(environment_atan2_approx(0.f, 0.f), 0.f);
}

// An environment map from per-texel values (the luminance is v; red carries a second pattern).
std::shared_ptr<Scene> scene_with_texels(const std::vector<float>& v, int w, int h, float rotation_deg) {
    auto scene = std::make_shared<Scene>();
    std::vector<vec4> texels(v.size());
    for (size_t i = 0; i < v.size(); ++i) texels[i] = vec4(v[i], v[i], v[i] * float(i % 3), 1.f);
    scene->textures.emplace_back(w, h, std::move(texels));
    scene->environment_map = 0;
    scene->environment.rotation_deg = rotation_deg;
    return scene;
}

// The environment cases: the 2D maps above (rotated by odd angles) plus a wide and a tall one for the margins.
struct EnvCase {
    std::shared_ptr<Scene> scene;
    std::string name;
};
std::vector<EnvCase> env_cases() {
    std::vector<EnvCase> cases;
    float rotation = 0.f;
    for (const Map& m : map_cases()) {
        cases.push_back({scene_with_texels(m.f, m.w, m.h, rotation), m.name});
        rotation += 47.f;
    }
    cases.push_back({scene_with_texels(random_weights(2048 * 2, 7), 2048, 2, 200.f), "2048x2"});
    cases.push_back({scene_with_texels(random_weights(3 * 1024, 8), 3, 1024, -30.f), "3x1024"});
    return cases;
}

// Map-space uv of a direction, in double (the reference for the texel search).
glm::dvec2 exact_uv(vec3 d, float rotation_deg) {
    const double theta = std::atan2(std::hypot(double(d.x), double(d.z)), double(d.y));
    double phi = std::atan2(-double(d.z), double(d.x)) - double(glm::radians(rotation_deg));
    phi -= 2.0 * M_PI * std::floor(phi / (2.0 * M_PI));
    return glm::dvec2(phi / (2.0 * M_PI), theta / M_PI);
}

vec3 random_direction(Pcg32& rng) {
    const float z = 1.f - 2.f * rng.next_float(), phi = 2.f * kPi * rng.next_float();
    const float r = std::sqrt(std::max(0.f, 1.f - z * z));
    return vec3(r * std::cos(phi), z, r * std::sin(phi));
}

// Away from texel edges (1e-4 texel, far above float rounding) the search finds the libm texel exactly; close to
// one it finds one of the two texels sharing it.
TEST(EnvironmentTexels, SearchAgreesWithTheExactTexelAwayFromEdges) {
    for (const EnvCase& c : env_cases()) {
        const Environment env(*c.scene);
        const Texture& map = c.scene->textures[0];
        Pcg32 rng(11, 3);
        int near_edges = 0;
        for (int s = 0; s < 200000; ++s) {
            const vec3 d = random_direction(rng) * (s % 2 ? 1.f : 3.7f);  // any length
            const glm::dvec2 a = exact_uv(d, c.scene->environment.rotation_deg) * glm::dvec2(map.width(), map.height());
            const ivec2 t = env.direction_to_texel(d);
            const glm::dvec2 dist_to_edge = glm::min(a - glm::floor(a), glm::ceil(a) - a);
            const ivec2 exact = glm::min(ivec2(glm::floor(a)), ivec2(map.width() - 1, map.height() - 1));
            if (dist_to_edge.x > 1e-4 && dist_to_edge.y > 1e-4) {
                ASSERT_EQ(t, exact) << c.name << " direction " << d.x << " " << d.y << " " << d.z;
            } else {
                ++near_edges;
                ASSERT_LE(std::abs(t.y - exact.y), 1) << c.name;
                const int dx = std::abs(t.x - exact.x);
                ASSERT_TRUE(dx <= 1 || dx == map.width() - 1) << c.name;
            }
        }
        EXPECT_LT(near_edges, 2000) << c.name;
    }
}

// eval() and pdf() pick the same texel for every direction, random or straddling an edge: pdf * 2 pi^2 sin(theta)
// / (luminance(eval) sin(theta at the texel's centre row)) is one constant over the map (the sampling weight is
// luminance * sin(centre theta)), and pdf = 0 exactly where eval is black.
TEST(EnvironmentTexels, PdfIsProportionalToEvalPerTexel) {
    for (const EnvCase& c : env_cases()) {
        const Environment env(*c.scene);
        const Texture& map = c.scene->textures[0];
        Pcg32 rng(13, 5);
        double lo = 1e300, hi = 0.0;
        for (int s = 0; s < 100000; ++s) {
            vec3 d = random_direction(rng);
            if (s % 2) {
                // Straddle an edge: a texel corner's direction nudged by less than float rounding of a texel.
                const vec2 uv(float(int(rng.next_float() * map.width())) / map.width(),
                              float(1 + int(rng.next_float() * (map.height() - 1))) / map.height());
                d = env.uv_to_direction(uv) + 2e-7f * random_direction(rng);
            }
            const float pdf = env.pdf(d), lum = luminance(env.eval(d));
            const float sin_theta = std::sqrt(d.x * d.x + d.z * d.z) / glm::length(d);
            if (!(sin_theta > 1e-6f)) continue;
            ASSERT_EQ(pdf == 0.f, lum == 0.f) << c.name << ": pdf " << pdf << " luminance " << lum;
            if (lum == 0.f) continue;
            const int row = env.direction_to_texel(d).y;
            const double centre = std::sin(M_PI * (row + 0.5) / map.height());
            const double k = double(pdf) * 2.0 * M_PI * M_PI * sin_theta / (double(lum) * centre);
            lo = std::min(lo, k);
            hi = std::max(hi, k);
        }
        EXPECT_LT(hi / lo - 1.0, 2e-5) << c.name << ": pdf / eval varies in [" << lo << ", " << hi << "]";
        EXPECT_GT(hi, 0.0) << c.name;
    }
}

// Samples histogrammed in exact (double) map uv, 3 x 3 sub-cells per texel, against pdf() integrated over each
// sub-cell with the Jacobian d omega = 2 pi^2 sin(theta) du dv (midpoint rule on a 6 x 6 sub-grid; the pdf is
// constant in u per texel and smooth in v). sample() returns eval() and pdf() of its direction but for float
// rounding at texel edges (a sample binned across an edge is allowed once per 1e5), and never a black texel.
TEST(EnvironmentSampling, UvChiSquareForOddMaps) {
    const auto cases = env_cases();
    for (const EnvCase& c : cases) {
        const Environment env(*c.scene);
        const Texture& map = c.scene->textures[0];
        const int bw = 3 * map.width(), bh = 3 * map.height(), sub = 6;
        if (size_t(bw) * size_t(bh) > 20000) continue;  // the wide and tall maps are covered by the texel tests
        const size_t samples = 300000;
        std::vector<double> observed(size_t(bw) * size_t(bh), 0.0), expected(observed.size(), 0.0);
        for (int y = 0; y < bh; ++y)
            for (int x = 0; x < bw; ++x) {
                double acc = 0.0;
                for (int j = 0; j < sub; ++j)
                    for (int i = 0; i < sub; ++i) {
                        const vec2 uv(float((x + (i + 0.5) / sub) / bw), float((y + (j + 0.5) / sub) / bh));
                        acc += double(env.pdf(env.uv_to_direction(uv))) * 2.0 * M_PI * M_PI * std::sin(M_PI * uv.y);
                    }
                expected[size_t(y) * bw + x] = acc / (sub * sub) / (double(bw) * double(bh)) * samples;
            }
        EXPECT_NEAR(std::accumulate(expected.begin(), expected.end(), 0.0) / samples, 1.0, 1e-3) << c.name;
        Pcg32 rng(17, 2);
        size_t failed = 0, mismatched = 0;
        for (size_t s = 0; s < samples; ++s) {
            const auto es = env.sample(vec2(rng.next_float(), rng.next_float()));
            if (!es) {
                ++failed;
                continue;
            }
            ASSERT_GT(es->pdf, 0.f) << c.name;
            ASSERT_GT(luminance(es->le), 0.f) << c.name << ": a black texel was sampled";
            // The pdf's sin(theta) comes from the sampled angle there and from the direction here: rounding apart.
            mismatched += std::fabs(es->pdf - env.pdf(es->wi)) > 1e-5f * es->pdf || es->le != env.eval(es->wi);
            const glm::dvec2 a = exact_uv(es->wi, c.scene->environment.rotation_deg) * glm::dvec2(bw, bh);
            observed[size_t(std::min(int(a.y), bh - 1)) * bw + size_t(std::min(int(a.x), bw - 1))] += 1.0;
        }
        EXPECT_LE(failed, samples / 100000) << c.name;
        EXPECT_LE(mismatched, samples / 100000) << c.name << ": sample() disagrees with eval()/pdf()";
        std::string why;
        EXPECT_GT(pooled_chi2_p(observed, expected, &why, double(samples) / 100000),
                  test::sidak_alpha(0.01, double(cases.size())))
            << c.name << ": " << why;
    }
}

}  // namespace
}  // namespace pv
