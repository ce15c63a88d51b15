// app/bench/raybench.cpp: ray generation (untimed) and timed tracing loops on a TBB arena (see raybench.h).
#include "app/bench/raybench.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <vector>

#include "core/base/parallel.h"
#include "core/render/surface.h"
#include "core/sampling/rng.h"
#include "core/sampling/warp.h"

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

// The random walk behind both the recorded ray sets and the minimal kernel: one jittered camera ray for pixel
// (x, y); from each hit, one shadow ray to a light sample (a point on an emitter or a direction toward the
// environment, chosen by TraceableScene::sample_light as the integrator chooses), built as the integrator builds it,
// and a cosine-distributed bounce, up to walk_depth bounces. Every surface is treated as white Lambertian.
// `camera_ray`, `bounce_ray` and `on_shadow` receive the rays; the closest-hit ones are traced here (the walk needs
// their hits), on_shadow decides what to do with its ray (built by the integrator's own pv::shadow_ray).
template <class OnCamera, class OnBounce, class OnShadow>
inline void random_walk(const TraceableScene& ts, const Camera& camera, int x, int y, int walk_depth, Pcg32& rng,
                        OnCamera&& camera_ray, OnBounce&& bounce_ray, OnShadow&& on_shadow) {
    auto u2 = [&] {
        const float a = rng.next_float();
        return vec2(a, rng.next_float());
    };
    Ray ray = camera.generate(vec2(float(x), float(y)) + u2(), u2());
    camera_ray(ray);
    for (int depth = 0; depth <= walk_depth; ++depth) {
        Hit hit;
        if (!ts.intersect(ray, hit)) break;
        const SurfacePoint sp = surface_point(ts.scene(), hit);
        const vec3 p = sp.p, e = sp.p_error;
        const vec3 n = glm::dot(sp.ng, ray.d) > 0.f ? -sp.ng : sp.ng;  // the side the ray came from
        if (ts.has_lights()) {
            const float u_sel = ts.light_selection_draw() ? rng.next_float() : 0.f;
            LightSample ls;
            if (ts.sample_light(p, n, u_sel, u2(), ls)) {
                const Ray s = pv::shadow_ray(offset_ray_origin(p, glm::dot(ls.wi, n) > 0.f ? n : -n, e), ls);
                on_shadow(s, ls.le * (std::fabs(glm::dot(ls.wi, n)) / ls.pdf));
            }
        }
        if (depth == walk_depth) break;
        const Frame frame(n);
        ray.o = offset_ray_origin(p, n, e);
        ray.d = glm::normalize(frame.to_world(square_to_cosine_hemisphere(u2())));
        ray.tmax = std::numeric_limits<float>::infinity();
        bounce_ray(ray);
    }
}

RaySets make_rays(const TraceableScene& ts, const Camera& camera, const RayBenchOptions& o) {
    RaySets sets;
    Pcg32 rng(o.seed, 0x6a09e667f3bcc909ull);
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x)
            random_walk(
                ts, camera, x, y, o.walk_depth, rng, [&](const Ray& r) { sets.camera.push_back(r); },
                [&](const Ray& r) { sets.bounce.push_back(r); }, [&](const Ray& r, vec3) { sets.shadow.push_back(r); });
    return sets;
}

// Seconds since construction: wall clock, or the process's CPU time divided by the thread count (cpu_clock).
class BenchClock {
public:
    BenchClock(bool cpu_clock, int threads)
        : m_cpu(cpu_clock),
          m_threads(threads),
          m_wall(std::chrono::steady_clock::now()),
          m_cpu_start(process_cpu_seconds()) {}
    double elapsed() const {
        return m_cpu ? (process_cpu_seconds() - m_cpu_start) / m_threads
                     : std::chrono::duration<double>(std::chrono::steady_clock::now() - m_wall).count();
    }

private:
    bool m_cpu;
    int m_threads;
    std::chrono::steady_clock::time_point m_wall;
    double m_cpu_start;
};

// Traces `rays` over and over for at least `seconds`, in chunks on the arena; returns rays per second.
template <typename Trace>
double time_rays(tbb::task_arena& arena, int threads, bool cpu_clock, const std::vector<Ray>& rays, double seconds,
                 Trace trace) {
    if (rays.empty()) return 0.0;
    const int chunk = 256;
    const int chunks = static_cast<int>((rays.size() + chunk - 1) / chunk);
    std::atomic<uint64_t> sink{0};
    uint64_t traced = 0;
    const BenchClock clock(cpu_clock, threads);
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
        elapsed = clock.elapsed();
    } while (elapsed < seconds);
    return double(traced) / elapsed;
}

}  // namespace

RayRates measure_ray_rates(const TraceableScene& ts, const Camera& camera, const RayBenchOptions& o) {
    const RaySets sets = make_rays(ts, camera, o);
    const int threads = o.threads > 0 ? o.threads : usable_cores();
    tbb::task_arena arena(threads);
    auto closest = [&](const Ray& r) -> uint64_t {
        Hit h;
        return ts.intersect(r, h) ? 1u : 0u;
    };
    auto shadow = [&](const Ray& r) -> uint64_t { return ts.occluded(r) ? 1u : 0u; };
    // Warm-up: touch the BVH and start the workers outside the timed loops.
    time_rays(arena, threads, false, sets.camera, 0.0, closest);
    RayRates rates;
    rates.camera = time_rays(arena, threads, o.cpu_clock, sets.camera, o.seconds_per_kind, closest);
    rates.bounce = time_rays(arena, threads, o.cpu_clock, sets.bounce, o.seconds_per_kind, closest);
    rates.shadow = time_rays(arena, threads, o.cpu_clock, sets.shadow, o.seconds_per_kind, shadow);
    return rates;
}

MinimalKernelRate measure_minimal_kernel(const TraceableScene& ts, const Camera& camera, const RayBenchOptions& o) {
    const int threads = o.threads > 0 ? o.threads : usable_cores();
    tbb::task_arena arena(threads);
    struct alignas(64) Row {
        uint64_t camera = 0, bounce = 0, shadow = 0;
        float sum = 0.f;  // the estimate, kept so that no work can be optimised away
    };
    std::vector<Row> rows(size_t(o.height));
    MinimalKernelRate out;
    double elapsed = 0.0;
    const BenchClock clock(o.cpu_clock, threads);
    uint32_t pass = 0;
    do {
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, o.height, 1), [&](const tbb::blocked_range<int>& r) {
                enable_ftz_daz();
                for (int y = r.begin(); y != r.end(); ++y) {
                    Row& row = rows[size_t(y)];
                    Pcg32 rng(hash_combine(o.seed, pass), uint64_t(y));
                    for (int x = 0; x < o.width; ++x)
                        random_walk(
                            ts, camera, x, y, o.walk_depth, rng, [&](const Ray&) { row.camera++; },
                            [&](const Ray&) { row.bounce++; },
                            [&](const Ray& s, vec3 contribution) {
                                row.shadow++;
                                if (!ts.occluded(s)) row.sum += contribution.x;
                            });
                }
            });
        });
        ++pass;
        elapsed = clock.elapsed();
    } while (elapsed < o.seconds_per_kind);
    double sum = 0.0;
    for (const Row& row : rows) {
        out.mix.camera += double(row.camera);
        out.mix.bounce += double(row.bounce);
        out.mix.shadow += double(row.shadow);
        sum += row.sum;
    }
    out.rays_per_second = out.mix.total() / elapsed;
    out.estimate = sum / out.mix.camera;
    return out;
}

}  // namespace pv
