// tests/test_path_walker.cpp: the path tracer advanced a stage at a time (PathWalker) and several paths interleaved
// per render thread (Renderer::render_pass) give the image of paths traced one at a time, bit for bit.
#include <gtest/gtest.h>

#include <cstring>

#include "core/environment.h"
#include "core/renderer.h"
#include "support/scenes.h"

namespace pv {
namespace {

// An open box (no ceiling) under a sky: a textured floor (an 8-bit checker with uvs), a mirror wall, a glossy wall, a
// glass ball and, with `emitter`, an emissive panel (then light sampling chooses between it and the sky; without it
// the sky is the only light and its sample is drawn at the hit). Every stage of the walker runs: textured and
// untextured hits, delta and non-delta BSDFs, escapes, emission found by BSDF sampling.
std::shared_ptr<Scene> open_box(bool emitter) {
    auto scene = std::make_shared<Scene>();
    std::vector<uint32_t> codes(8 * 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) codes[size_t(y * 8 + x)] = ((x + y) & 1) ? 0xff2040c0u : 0xffe0d0a0u;
    scene->textures.push_back(Texture(8, 8, codes));
    Material floor;
    floor.base_color_texture = 0;
    const uint32_t m_floor = test::add_material(*scene, floor);
    Material wall;
    wall.bsdf = Lambertian{vec3(0.6f, 0.5f, 0.4f)};
    const uint32_t m_wall = test::add_material(*scene, wall);
    Material mirror;
    mirror.bsdf = Mirror{vec3(0.9f)};
    const uint32_t m_mirror = test::add_material(*scene, mirror);
    Material glossy;
    glossy.bsdf = Glossy{vec3(0.3f, 0.4f, 0.3f), vec3(0.2f), 0.15f};
    const uint32_t m_glossy = test::add_material(*scene, glossy);
    Material glass;
    glass.bsdf = Dielectric{1.5f};
    const uint32_t m_glass = test::add_material(*scene, glass);

    // The floor's two triangles (add_quad: (p0 p1 p2), (p0 p2 p3)) with uvs; the checker repeats twice across it.
    test::add_quad(*scene, vec3(-1, 0, -1), vec3(-1, 0, 1), vec3(1, 0, 1), vec3(1, 0, -1), m_floor);
    scene->uvs = {vec2(0.f, 0.f), vec2(0.f, 2.f), vec2(2.f, 2.f), vec2(2.f, 0.f)};
    scene->uv_indices = {uvec3(0, 1, 2), uvec3(0, 2, 3)};  // later triangles get none (Scene::add_triangle)
    test::add_quad(*scene, vec3(-1, 0, -1), vec3(1, 0, -1), vec3(1, 1.5f, -1), vec3(-1, 1.5f, -1), m_wall);
    test::add_quad(*scene, vec3(-1, 0, 1), vec3(-1, 0, -1), vec3(-1, 1.5f, -1), vec3(-1, 1.5f, 1), m_mirror);
    test::add_quad(*scene, vec3(1, 0, -1), vec3(1, 0, 1), vec3(1, 1.5f, 1), vec3(1, 1.5f, -1), m_glossy);
    test::add_icosphere(*scene, vec3(0.3f, 0.35f, 0.f), 0.3f, 2, m_glass);
    if (emitter) {
        Material light;
        light.emission = vec3(6.f);
        const uint32_t m_light = test::add_material(*scene, light);
        test::add_quad(*scene, vec3(-0.4f, 1.4f, -0.4f), vec3(0.4f, 1.4f, -0.4f), vec3(0.4f, 1.4f, 0.4f),
                       vec3(-0.4f, 1.4f, 0.4f), m_light);
    }
    scene->textures.push_back(make_default_sky());
    scene->environment_map = uint32_t(scene->textures.size() - 1);
    scene->camera.eye = vec3(0.f, 1.2f, 2.6f);
    scene->camera.target = vec3(0.f, 0.4f, 0.f);
    scene->camera.vfov_deg = 50.f;
    scene->has_camera = true;
    return scene;
}

bool same_bits(vec3 a, vec3 b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Paths advanced in a pseudo-random order, several at a time, each with its own sampler, against the same paths
// traced one at a time by trace_path: the same radiance and counts, bit for bit. Fails if any of a path's state lives
// outside its walker (shared between the paths in flight) or is not carried from one stage to the next.
TEST(PathWalker, InterleavedPathsMatchOneAtATime) {
    for (const bool emitter : {false, true}) {
        for (const SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Independent}) {
            SCOPED_TRACE(std::string(emitter ? "emitter and sky" : "sky only") + ", " + sampler_name(kind));
            const auto scene = open_box(emitter);
            const test::Tracer tracer(scene);
            const ScopedFtzDaz ftz;
            RenderSettings settings;
            settings.sampler = kind;
            settings.seed = 7;
            const int width = 16, height = 12, spp = 3;
            const Camera camera(scene->camera, width, height);
            struct Job {
                int x, y;
                uint32_t index;
            };
            std::vector<Job> jobs;
            std::vector<vec3> expected;
            std::vector<PathCounters> expected_counts;
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x)
                    for (uint32_t i = 0; i < uint32_t(spp); ++i) {
                        Sampler sampler(settings.seed, settings.sampler);
                        PathCounters c;
                        expected.push_back(
                            trace_path(tracer, settings, camera_ray(camera, sampler, x, y, i), sampler, c));
                        expected_counts.push_back(c);
                        jobs.push_back({x, y, i});
                    }

            constexpr int kSlots = 5;
            struct Slot {
                PathWalker walker;
                Sampler sampler;
                size_t job = 0;
                bool busy = false;
            };
            std::vector<Slot> slots(kSlots);
            size_t next = 0, done = 0, steps = 0;
            auto start = [&](Slot& s) {
                s.busy = next < jobs.size();
                if (!s.busy) return;
                s.job = next++;
                s.sampler = Sampler(settings.seed, settings.sampler);
                const Job& j = jobs[s.job];
                s.walker.start(tracer, settings, camera_ray(camera, s.sampler, j.x, j.y, j.index), s.sampler);
            };
            for (Slot& s : slots) start(s);
            Pcg32 order(12345u, 1u);
            while (done < jobs.size()) {
                Slot& s = slots[order.next_u32() % kSlots];
                if (!s.busy) continue;
                ++steps;
                if (s.walker.step()) continue;
                ++done;
                ASSERT_TRUE(same_bits(s.walker.radiance(), expected[s.job]))
                    << "path " << s.job << ": " << s.walker.radiance().x << " against " << expected[s.job].x;
                const PathCounters& c = s.walker.counters();
                const PathCounters& e = expected_counts[s.job];
                ASSERT_EQ(c.rays, e.rays);
                ASSERT_EQ(c.shadow_rays, e.shadow_rays);
                ASSERT_EQ(c.vertices, e.vertices);
                ASSERT_EQ(c.paths, 1u);
                start(s);
            }
            // The paths did wait: more steps than paths (a path that never hit would take one).
            EXPECT_GT(steps, 3 * jobs.size());
        }
    }
}

// The Renderer's passes (2 threads) with 1, 3 and 8 paths in flight per thread: the same film sums, counts and ray
// totals, bit for bit, with adaptive sampling by allocation (each pixel its own sample indices and its ray counts) and
// without. A Threading* suite, so that it also runs under TSan.
TEST(ThreadingPathsInFlight, ImageDoesNotDependOnPathsInFlight) {
    const auto scene = open_box(false);
    for (const bool allocate : {false, true}) {
        SCOPED_TRACE(allocate ? "adaptive allocation" : "uniform");
        std::vector<Film> films;
        std::vector<uint64_t> rays;
        for (const int in_flight : {1, 3, 8}) {
            Renderer r(scene, 2);
            r.set_paths_in_flight(in_flight);
            ASSERT_EQ(r.paths_in_flight(), in_flight);
            AdaptiveSettings adaptive;
            adaptive.allocate = allocate;
            adaptive.min_spp = 4;
            r.set_adaptive(adaptive);
            RenderSettings settings;
            settings.sky_guide = SkyGuideMode::Off;
            r.restart(scene->camera, settings, 20, 14);
            for (int pass = 0; pass < 12; ++pass) r.render_pass();
            films.push_back(r.film());
            rays.push_back(r.stats().rays + r.stats().shadow_rays);
        }
        for (size_t k = 1; k < films.size(); ++k) {
            EXPECT_EQ(rays[k], rays[0]);
            for (int y = 0; y < 14; ++y)
                for (int x = 0; x < 20; ++x) {
                    const FilmPixel& a = films[0].pixel(x, y);
                    const FilmPixel& b = films[k].pixel(x, y);
                    ASSERT_EQ(a.n, b.n) << x << "," << y;
                    ASSERT_EQ(std::memcmp(a.sum, b.sum, sizeof a.sum), 0) << x << "," << y;
                    ASSERT_EQ(std::memcmp(a.sum_sq, b.sum_sq, sizeof a.sum_sq), 0) << x << "," << y;
                    ASSERT_EQ(std::memcmp(a.sum_even, b.sum_even, sizeof a.sum_even), 0) << x << "," << y;
                }
        }
    }
}

// Interleaving where the hit data outgrows the caches, not on a small scene (where it only costs the switching).
TEST(PathWalker, InterleavesOnlyScenesLargerThanTheCaches) {
    EXPECT_EQ(Renderer(test::cornell_box(), 1).paths_in_flight(), 1);
    auto big = std::make_shared<Scene>();
    test::add_icosphere(*big, vec3(0.f), 1.f, 6, test::add_material(*big, Material{}));  // 81920 triangles
    Renderer r(big, 1);
    EXPECT_EQ(r.paths_in_flight(), 4);
    EXPECT_GT(big->triangles.size() * sizeof(TriangleRecord), kInterleaveBytes);
}

}  // namespace
}  // namespace pv
