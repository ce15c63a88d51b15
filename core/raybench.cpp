// core/raybench.cpp: ray generation (untimed) and timed tracing loops on a TBB arena (see raybench.h).
#include "core/raybench.h"

#include "core/rng.h"
#include "core/warp.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <time.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace pv {

double process_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double RayRates::mix_rate(const RayMix& mix) const {
    double t = 0.0;
    if (mix.camera > 0.0) t += camera > 0.0 ? mix.camera / camera : 0.0;
    if (mix.bounce > 0.0) t += bounce > 0.0 ? mix.bounce / bounce : 0.0;
    if (mix.shadow > 0.0) t += shadow > 0.0 ? mix.shadow / shadow : 0.0;
    return t > 0.0 ? mix.total() / t : 0.0;
}

namespace {

struct RaySets {
    std::vector<Ray> camera, bounce, shadow;
};

// Geometric normal of triangle `prim`.
vec3 normal_of(const Scene& s, uint32_t prim) {
    const uvec3 t = s.triangles[prim];
    return glm::normalize(glm::cross(s.positions[t.y] - s.positions[t.x], s.positions[t.z] - s.positions[t.x]));
}

vec3 point_of(const Scene& s, const Hit& h) {
    const uvec3 t = s.triangles[h.prim];
    return (1.f - h.u - h.v) * s.positions[t.x] + h.u * s.positions[t.y] + h.v * s.positions[t.z];
}

// One jittered camera ray per pixel; from each hit a random walk of cosine-distributed bounce rays, and at each
// vertex one shadow ray to a light sample, built as the integrator builds them.
RaySets make_rays(const Scene& scene, const Accel& accel, const LightSet& lights, const Environment& env,
                  const Camera& camera, const RayBenchOptions& o) {
    RaySets sets;
    Pcg32 rng(o.seed, 0x6a09e667f3bcc909ull);
    auto u2 = [&] {
        const float a = rng.next_float();
        return vec2(a, rng.next_float());
    };
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            Ray ray = camera.generate(vec2(float(x), float(y)) + u2(), u2());
            sets.camera.push_back(ray);
            for (int depth = 0; depth <= o.walk_depth; ++depth) {
                Hit hit;
                if (!accel.intersect(ray, hit)) break;
                const vec3 p = point_of(scene, hit);
                vec3 n = normal_of(scene, hit.prim);
                if (glm::dot(n, ray.d) > 0.f) n = -n;  // the side the ray came from
                // Shadow ray to a light point (or toward the environment when there are no emitters).
                if (!lights.empty()) {
                    const float u_sel = rng.next_float();
                    if (auto ls = lights.sample(p, u_sel, u2())) {
                        Ray s;
                        s.o = offset_ray_origin(p, glm::dot(ls->wi, n) > 0.f ? n : -n);
                        s.d = offset_ray_origin(ls->p, glm::dot(ls->wi, ls->n) < 0.f ? ls->n : -ls->n) - s.o;
                        s.tmax = 1.f - 1e-4f;
                        sets.shadow.push_back(s);
                    }
                } else if (!env.is_black()) {
                    if (auto es = env.sample(u2())) {
                        Ray s;
                        s.o = offset_ray_origin(p, glm::dot(es->wi, n) > 0.f ? n : -n);
                        s.d = es->wi;
                        sets.shadow.push_back(s);
                    }
                }
                if (depth == o.walk_depth) break;
                const Frame frame(n);
                ray.o = offset_ray_origin(p, n);
                ray.d = glm::normalize(frame.to_world(square_to_cosine_hemisphere(u2())));
                ray.tmax = std::numeric_limits<float>::infinity();
                sets.bounce.push_back(ray);
            }
        }
    return sets;
}

// Traces `rays` over and over for at least `seconds`, in chunks on the arena; returns rays per second.
template <typename Trace>
double time_rays(tbb::task_arena& arena, int threads, bool cpu_clock, const std::vector<Ray>& rays, double seconds,
                 Trace trace) {
    if (rays.empty()) return 0.0;
    const int chunk = 256;
    const int chunks = static_cast<int>((rays.size() + chunk - 1) / chunk);
    std::atomic<uint64_t> sink{0};
    uint64_t traced = 0;
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    double elapsed = 0.0;
    do {
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, chunks, 1), [&](const tbb::blocked_range<int>& r) {
                enable_ftz_daz();
                uint64_t local = 0;
                for (int c = r.begin(); c != r.end(); ++c) {
                    const size_t end = std::min(rays.size(), size_t(c + 1) * chunk);
                    for (size_t i = size_t(c) * chunk; i < end; ++i) local += trace(rays[i]);
                }
                sink.fetch_add(local, std::memory_order_relaxed);
            });
        });
        traced += rays.size();
        elapsed = cpu_clock ? (process_cpu_seconds() - cpu_start) / threads
                            : std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } while (elapsed < seconds);
    return double(traced) / elapsed;
}

}  // namespace

RayRates measure_ray_rates(const Scene& scene, const Accel& accel, const LightSet& lights, const Environment& env,
                           const Camera& camera, const RayBenchOptions& o) {
    const RaySets sets = make_rays(scene, accel, lights, env, camera, o);
    const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    tbb::task_arena arena(threads);
    auto closest = [&](const Ray& r) -> uint64_t {
        Hit h;
        return accel.intersect(r, h) ? 1u : 0u;
    };
    auto shadow = [&](const Ray& r) -> uint64_t { return accel.occluded(r) ? 1u : 0u; };
    // Warm-up: touch the BVH and start the workers outside the timed loops.
    time_rays(arena, threads, false, sets.camera, 0.0, closest);
    RayRates rates;
    rates.camera = time_rays(arena, threads, o.cpu_clock, sets.camera, o.seconds_per_kind, closest);
    rates.bounce = time_rays(arena, threads, o.cpu_clock, sets.bounce, o.seconds_per_kind, closest);
    rates.shadow = time_rays(arena, threads, o.cpu_clock, sets.shadow, o.seconds_per_kind, shadow);
    return rates;
}

}  // namespace pv
