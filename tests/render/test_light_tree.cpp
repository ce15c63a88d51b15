// The light tree (core/render/light_tree.h): its pick probabilities, recomputed by re-walking the tree along an
// emitter's bit trail, sum to 1 over the emitters and are the frequencies the pick draws them with (chi-square);
// through LightSet, a sample's pdf equals the pdf a BSDF-found emitter is given at the same point. The tree's agreement
// with the closed forms under every estimator is in tests/render/test_light_matrix.cpp.
// Test kinds: unit; statistical: LightTreeSampling
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/partial/partial.h"
#include "core/render/light_tree.h"
#include "core/render/lights.h"
#include "core/sampling/rng.h"
#include "core/sampling/warp.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

struct RandomTri {
    vec3 p0, p1, p2;
    float le;
    bool two_sided;
};

vec3 random_unit(Pcg32& g) { return square_to_uniform_sphere(vec2(g.next_float(), g.next_float())); }

// n triangles around the origin (centres in a box of half side `extent`, sides up to `size`), radiances over four
// decades, a third two-sided.
std::vector<RandomTri> random_tris(int n, uint64_t seed, float extent = 2.f, float size = 0.3f) {
    Pcg32 g(seed, 5);
    std::vector<RandomTri> tris;
    for (int i = 0; i < n; ++i) {
        const vec3 c = extent * (2.f * vec3(g.next_float(), g.next_float(), g.next_float()) - 1.f);
        const float s = size * (0.2f + g.next_float());
        RandomTri t{c + s * random_unit(g), c + s * random_unit(g), c + s * random_unit(g),
                    std::pow(10.f, 4.f * g.next_float() - 2.f), g.next_float() < 0.33f};
        tris.push_back(t);
    }
    return tris;
}

std::vector<LightBounds> bounds_of(const std::vector<RandomTri>& tris) {
    std::vector<LightBounds> b;
    for (const RandomTri& t : tris) {
        const float area = 0.5f * glm::length(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
        b.push_back(triangle_light_bounds(t.p0, t.p1, t.p2, t.le * area * (t.two_sided ? 2.f : 1.f), t.two_sided));
    }
    return b;
}

// Shading points: inside and outside the lights' box, with a normal or none.
struct Receiver {
    vec3 p, n;
};
std::vector<Receiver> receivers(uint64_t seed, int count) {
    Pcg32 g(seed, 9);
    std::vector<Receiver> r;
    for (int i = 0; i < count; ++i) {
        const vec3 p = 3.f * (2.f * vec3(g.next_float(), g.next_float(), g.next_float()) - 1.f);
        r.push_back({p, i % 4 == 3 ? vec3(0.f) : random_unit(g)});
    }
    return r;
}

// Two-sided emitters can always reach a point (their importance is never 0 but edge-on): the pmf sums to 1. One-sided
// ones facing away have importance 0: a subtree whose every emitter faces away while its bounds do not is a dead
// end, where the pick fails (pbrt-v4's BVHLightSampler does the same); the pmf then sums to 1 minus that
// probability, which Chi2PicksFollowThePmf checks as a cell of its own.
TEST(LightTree, PmfSumsToOneOverTheEmitters) {
    for (const bool two_sided : {true, false})
        for (const int n : {1, 2, 3, 17, 300, 2000}) {
            std::vector<LightBounds> b = bounds_of(random_tris(n, uint64_t(n)));
            if (two_sided)
                for (LightBounds& l : b) l.two_sided = true;
            const LightTree tree(b);
            ASSERT_FALSE(tree.empty());
            // Wide nodes of at least two children each (one: the single emitter's root).
            EXPECT_LE(tree.node_count(), size_t(std::max(1, n - 1)));
            for (const Receiver& r : receivers(uint64_t(n) + 1, 40)) {
                double sum = 0.0;
                for (uint32_t k = 0; k < uint32_t(n); ++k) {
                    const float p = tree.pmf(k, r.p, r.n);
                    EXPECT_GE(p, 0.f);
                    sum += double(p);
                }
                // Each pmf is a product of at most depth float ratios: relative rounding depth x 2^-24 each.
                if (two_sided)
                    EXPECT_NEAR(sum, 1.0, 1e-5) << n << " lights";
                else
                    EXPECT_LE(sum, 1.0 + 1e-5) << n << " lights";
            }
        }
}

// A tree of at most kWidth emitters whose binary tree is at most kWidthLog2 deep is one node: the pick chooses
// among them directly, in proportion to their importances computed four at a time (SSE), which agree with
// LightBounds::importance up to rounding (every lane of the node: the first seed giving one node for each count).
TEST(LightTree, ANodePicksInProportionToTheImportances) {
    for (int n = 2; n <= LightTree::kWidth; ++n) {
        std::vector<LightBounds> b;
        for (uint64_t seed = 0; seed < 200 && b.empty(); ++seed) {
            b = bounds_of(random_tris(n, 1000 * uint64_t(n) + seed));
            if (LightTree(b).node_count() != 1) b.clear();
        }
        ASSERT_FALSE(b.empty()) << n << " lights: no seed gives a one-node tree";
        const LightTree tree(b);
        int compared = 0;
        for (const Receiver& r : receivers(uint64_t(50 + n), 200)) {
            double sum = 0.0;
            for (const LightBounds& l : b) sum += double(l.importance(r.p, r.n));
            if (!(sum > 0.0)) continue;
            for (uint32_t k = 0; k < uint32_t(n); ++k) {
                const double expected = double(b[k].importance(r.p, r.n)) / sum;
                EXPECT_NEAR(double(tree.pmf(k, r.p, r.n)), expected, 1e-5 * expected + 1e-6) << n << " lights, " << k;
            }
            ++compared;
        }
        EXPECT_GT(compared, 100);
    }
}

// Many emitters in one place (no split separates them): halves by count keep the tree within its 64-bit trails.
TEST(LightTree, CoincidentEmittersStayWithinTheBitTrail) {
    std::vector<LightBounds> b(5000, triangle_light_bounds(vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0), 1.f, false));
    const LightTree tree(b);
    EXPECT_LT(tree.depth(), 64);
    double sum = 0.0;
    for (uint32_t k = 0; k < b.size(); ++k) sum += double(tree.pmf(k, vec3(0.2f, 0.2f, 1.f), vec3(0.f, 0.f, -1.f)));
    EXPECT_NEAR(sum, 1.0, 1e-4);
    EXPECT_NEAR(double(tree.pmf(7, vec3(0.2f, 0.2f, 1.f), vec3(0.f))), 1.0 / 5000.0, 1e-8);
}

// Emitters that cannot reach the point (one-sided, facing away) are never picked and have pmf 0; the rest keep
// their whole probability.
TEST(LightTree, EmittersFacingAwayAreNeverPicked) {
    std::vector<LightBounds> b;
    for (int i = 0; i < 8; ++i) {
        const float x = float(i);
        // Even: facing +z (toward the point above), odd: facing -z.
        const vec3 p1 = i % 2 ? vec3(x, 1, 0) : vec3(x + 1, 0, 0), p2 = i % 2 ? vec3(x + 1, 0, 0) : vec3(x, 1, 0);
        b.push_back(triangle_light_bounds(vec3(x, 0, 0), p1, p2, 1.f + x, false));
    }
    const LightTree tree(b);
    const vec3 p(4.f, 0.5f, 3.f), n(0.f, 0.f, -1.f);
    double sum = 0.0;
    for (uint32_t k = 0; k < 8; ++k) {
        const float pmf = tree.pmf(k, p, n);
        if (k % 2)
            EXPECT_EQ(pmf, 0.f) << k;
        else
            EXPECT_GT(pmf, 0.f) << k;
        sum += double(pmf);
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
    Pcg32 g(1, 2);
    for (int i = 0; i < 2000; ++i) {
        uint32_t k = 0;
        float pmf = 0.f;
        ASSERT_TRUE(tree.sample(p, n, g.next_float(), &k, &pmf));
        EXPECT_EQ(k % 2, 0u);
    }
}

// The picks' frequencies are the pmf (chi-square over the emitters and the failed picks, cells of expected count
// below 5 pooled), and
// each pick's probability is the pmf recomputed along its bit trail, bit for bit.
TEST(LightTreeSampling, Chi2PicksFollowThePmf) {
    const int n = 150;
    const std::vector<LightBounds> b = bounds_of(random_tris(n, 77));
    const LightTree tree(b);
    const std::vector<Receiver> rs = receivers(78, 8);
    const double level = test::sidak_alpha(0.01, double(rs.size()));
    const int samples = 200000;
    for (size_t ri = 0; ri < rs.size(); ++ri) {
        const Receiver& r = rs[ri];
        std::vector<double> count(size_t(n), 0.0);
        Pcg32 g(1234, ri);
        int mismatched = 0, failed = 0;
        for (int i = 0; i < samples; ++i) {
            uint32_t k = 0;
            float pmf = 0.f;
            if (!tree.sample(r.p, r.n, g.next_float(), &k, &pmf)) {
                ++failed;
                continue;
            }
            count[k] += 1.0;
            if (pmf != tree.pmf(k, r.p, r.n)) ++mismatched;
        }
        EXPECT_EQ(mismatched, 0);
        double chi2 = 0.0, pooled_obs = 0.0, pooled_exp = 0.0, sum = 0.0;
        int cells = 0;
        for (uint32_t k = 0; k < uint32_t(n); ++k) sum += double(tree.pmf(k, r.p, r.n));
        // The failed picks (dead ends): a cell of probability 1 - sum.
        const double e_failed = double(samples) * std::max(0.0, 1.0 - sum);
        if (e_failed >= 5.0) {
            chi2 += (double(failed) - e_failed) * (double(failed) - e_failed) / e_failed;
            ++cells;
        } else {
            pooled_obs += double(failed);
            pooled_exp += e_failed;
        }
        for (uint32_t k = 0; k < uint32_t(n); ++k) {
            const double e = double(samples) * double(tree.pmf(k, r.p, r.n));
            if (e < 5.0) {
                pooled_obs += count[k];
                pooled_exp += e;
                continue;
            }
            chi2 += (count[k] - e) * (count[k] - e) / e;
            ++cells;
        }
        if (pooled_exp > 0.0 || pooled_obs > 0.0) {
            chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / std::max(pooled_exp, 1e-3);
            ++cells;
        }
        const double p = test::chi2_p_value(chi2, double(cells - 1));
        EXPECT_GT(p, level) << "receiver " << ri << ": chi2 " << chi2 << " over " << cells - 1 << " dof";
    }
}

// ------------------------------------------------------------------------------- through LightSet

Scene random_emitters(int n, uint64_t seed, float extent, float size) {
    Scene scene;
    for (const RandomTri& t : random_tris(n, seed, extent, size)) {
        Material m;
        m.emission = vec3(t.le);
        m.two_sided_emission = t.two_sided;
        scene.add_triangle(t.p0, t.p1, t.p2, test::add_material(scene, m));
    }
    return scene;
}

// Where the ray from ref along w crosses triangle i (Moller-Trumbore in double): its distance, or -1.
double crossing(const Scene& scene, uint32_t i, vec3 ref, vec3 w) {
    const uvec3 t = scene.triangles[i];
    const dvec3 p0 = scene.positions[t.x], p1 = scene.positions[t.y], p2 = scene.positions[t.z];
    const dvec3 o = ref, d = w, e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
    const double det = glm::dot(e1, pv);
    if (det == 0.0) return -1.0;
    const dvec3 tv = o - p0;
    const double u = glm::dot(tv, pv) / det;
    const dvec3 qv = glm::cross(tv, e1);
    const double v = glm::dot(d, qv) / det, tt = glm::dot(e2, qv) / det;
    if (u < 0 || v < 0 || u + v > 1 || tt <= 0) return -1.0;
    return tt;
}

// A sample's pdf is what pdf() gives the emitter it lies on at that point (what MIS weighs a BSDF-found emitter
// with), under both point rules (near emitters by solid angle, far ones by area).
TEST(LightTree, SamplePdfEqualsThePdfOfTheFoundEmitter) {
    const Scene scene = random_emitters(60, 21, 2.f, 0.4f);
    LightSet lights(scene, scene.materials);
    lights.set_sampler(LightSamplerKind::Tree);
    ASSERT_EQ(lights.sampler(), LightSamplerKind::Tree);
    int checked = 0;
    for (const Receiver& r : receivers(22, 12)) {
        Pcg32 g(5, uint64_t(checked));
        for (int i = 0; i < 4000; ++i) {
            LightSample ls;
            const float us = g.next_float();
            const vec2 u(g.next_float(), g.next_float());
            if (!lights.sample(r.p, r.n, us, u, ls)) continue;
            // The emitter the point lies on: the crossing nearest to ls.dist.
            uint32_t best = kNoIndex;
            double best_err = 1e-3 * double(ls.dist);
            for (uint32_t k = 0; k < scene.triangles.size(); ++k) {
                const double t = crossing(scene, k, r.p, ls.wi);
                if (t >= 0.0 && std::fabs(t - double(ls.dist)) < best_err) {
                    best_err = std::fabs(t - double(ls.dist));
                    best = k;
                }
            }
            if (best == kNoIndex) continue;  // the ray misses its own triangle by rounding at an edge
            const float pdf = lights.pdf(best, r.p, r.n, ls.p, ls.n);
            // Equal but for the rounding of the area rule's cosine at the emitter, computed from d / |d| in one and
            // from d then divided by |d| in the other: a few ulps of d over the cosine.
            const float cos_l = std::fabs(glm::dot(ls.n, ls.wi));
            ASSERT_NEAR(pdf, ls.pdf, ls.pdf * (1e-6f + 1e-6f / cos_l)) << "emitter " << best << " cos " << cos_l;
            ++checked;
        }
    }
    EXPECT_GT(checked, 40000);
}

}  // namespace
}  // namespace pv

namespace pv {
namespace {

// The light sampler is part of the settings string partial renders record (core/partial/partial.cpp): a tree render's
// parts say so and read back as such, so a merge refuses to mix them with power parts; a power render's string is the
// one of before the tree.
TEST(LightSamplerSettings, RoundTripThroughTheSettingsString) {
    RenderSettings power, tree;
    tree.light_sampler = LightSamplerKind::Tree;
    EXPECT_EQ(power.describe().find("light_sampler"), std::string::npos);
    EXPECT_NE(tree.describe().find(" light_sampler=tree"), std::string::npos);
    EXPECT_EQ(parse_settings(tree.describe(), "t"), tree);
    EXPECT_EQ(parse_settings(power.describe(), "t"), power);
    EXPECT_NE(power.describe(), tree.describe());
    EXPECT_NE(power, tree);
}

}  // namespace
}  // namespace pv
