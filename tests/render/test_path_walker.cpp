// tests/render/test_path_walker.cpp: the path tracer advanced a stage at a time (PathWalker) gives the paths traced one
// at a time, bit for bit, however several are interleaved (the Renderer's interleaving:
// test_threading_paths_in_flight.cpp).
// Test kinds: unit
#include <gtest/gtest.h>

#include <cstring>

#include "core/frame/renderer.h"
#include "support/scenes.h"

namespace pv {
namespace {

bool same_bits(vec3 a, vec3 b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Paths advanced in a pseudo-random order, several at a time, each with its own sampler, against the same paths
// traced one at a time by trace_path: the same radiance and counts, bit for bit. Fails if any of a path's state lives
// outside its walker (shared between the paths in flight) or is not carried from one stage to the next.
TEST(PathWalker, InterleavedPathsMatchOneAtATime) {
    for (const bool emitter : {false, true}) {
        for (const SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Independent}) {
            SCOPED_TRACE(std::string(emitter ? "emitter and sky" : "sky only") + ", " + sampler_name(kind));
            const auto scene = test::open_box(emitter);
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

// Interleaving where the hit data outgrows the caches, not on a small scene (where it only costs the switching).
// An observer (PathObserver: the sky guide's training watches its paths with one) changes nothing in the path, sees
// every light sample it adds: without MIS and without delta BSDFs, a path's radiance is the emission its camera ray
// sees (the same path with max_depth 0) plus the light samples' radiance that light() reports, in the order they were
// added; and vertex() comes at least once before each light sample, with a throughput no larger than the path's start.
TEST(PathWalker, ObserverSeesEveryLightSampleAndChangesNothing) {
    struct Watch final : PathObserver {
        vec3 sum{0.f};
        int vertices = 0, lights = 0;
        bool ordered = true, draws_in_range = true, beta_bounded = true;
        void vertex(const PathVertex& v) override {
            ++vertices;
            beta_bounded = beta_bounded && max_component(v.beta) <= 2.f * kRouletteThroughput + 1.f;
        }
        void light(const LightSample&, float u_select, vec2 u, vec3 added) override {
            ordered = ordered && vertices > lights;
            draws_in_range = draws_in_range && u_select >= 0.f && u_select < 1.f && u.x >= 0.f && u.x < 1.f &&
                             u.y >= 0.f && u.y < 1.f;
            ++lights;
            sum += added;
        }
    };
    const auto scene = test::cornell_box();  // no delta BSDF: emission after a bounce is light sampling's alone
    const test::Tracer tracer(scene);
    const ScopedFtzDaz ftz;
    RenderSettings settings;
    settings.sampler = SamplerKind::Independent;
    settings.mis = false;
    settings.seed = 3;
    RenderSettings direct = settings;
    direct.max_depth = 0;
    const Camera camera(scene->camera, 16, 12);
    int lights = 0;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 16; ++x) {
            Sampler sampler(settings.seed, settings.sampler);
            PathCounters c0, c1, cd;
            const vec3 plain = trace_path(tracer, settings, camera_ray(camera, sampler, x, y, 0), sampler, c0);
            const vec3 seen = trace_path(tracer, direct, camera_ray(camera, sampler, x, y, 0), sampler, cd);
            Watch watch;
            PathWalker w;
            w.start(tracer, settings, camera_ray(camera, sampler, x, y, 0), sampler);
            w.observe(&watch);
            while (w.step()) {
            }
            c1 = w.counters();
            ASSERT_TRUE(same_bits(plain, w.radiance())) << x << "," << y;
            EXPECT_EQ(c0.rays, c1.rays);
            EXPECT_EQ(c0.shadow_rays, c1.shadow_rays);
            EXPECT_EQ(c0.vertices, c1.vertices);
            EXPECT_TRUE(watch.ordered && watch.draws_in_range && watch.beta_bounded) << x << "," << y;
            EXPECT_LE(uint64_t(watch.lights), c1.shadow_rays);
            EXPECT_LE(uint64_t(watch.vertices), c1.vertices);
            const vec3 expected = seen + watch.sum;
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(w.radiance()[k], expected[k], 1e-5f * (1.f + expected[k])) << x << "," << y << " " << k;
            lights += watch.lights;
        }
    EXPECT_GT(lights, 100);  // not vacuous: most paths see lights
}

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
