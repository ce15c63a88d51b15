// microbench/quads_vs_triangles.cpp: does keeping OBJ quads as Embree quads (RTC_GEOMETRY_TYPE_QUAD) trace faster
// than triangulating them (issue: "quads kept as Embree quads where that is faster (measured)")?
// The same displaced grid of N x N quads is built both ways; random incoherent rays (origins above the surface,
// uniform directions) and shadow rays are traced with rtcIntersect1 / rtcOccluded1 on one thread.
// Reports rays/s, BVH build time and bytes per primitive pair.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/glm.hpp>
#include <random>
#include <vector>

namespace {

constexpr int kGrid = 700;  // 490k quads = 980k triangles

struct Built {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    double build_seconds = 0.0;
    int64_t bytes = 0;
};

std::atomic<int64_t> g_bytes{0};
bool on_memory(void*, ssize_t bytes, bool) {
    g_bytes += bytes;
    return true;
}

Built build(bool quads) {
    Built b;
    b.device = rtcNewDevice(nullptr);
    rtcSetDeviceMemoryMonitorFunction(b.device, on_memory, nullptr);
    g_bytes = 0;
    const auto start = std::chrono::steady_clock::now();
    b.scene = rtcNewScene(b.device);
    RTCGeometry g = rtcNewGeometry(b.device, quads ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
    const int nv = (kGrid + 1) * (kGrid + 1);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, nv));
    for (int j = 0; j <= kGrid; ++j)
        for (int i = 0; i <= kGrid; ++i) {
            float* p = v + 3 * (j * (kGrid + 1) + i);
            p[0] = float(i) / kGrid;
            p[1] = 0.05f * std::sin(i * 0.21f) * std::cos(j * 0.17f);
            p[2] = float(j) / kGrid;
        }
    if (quads) {
        auto* idx = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 16, size_t(kGrid) * kGrid));
        for (int j = 0; j < kGrid; ++j)
            for (int i = 0; i < kGrid; ++i) {
                const unsigned a = unsigned(j * (kGrid + 1) + i);
                unsigned* q = idx + 4 * (j * kGrid + i);
                q[0] = a;
                q[1] = a + 1;
                q[2] = a + kGrid + 2;
                q[3] = a + kGrid + 1;
            }
    } else {
        auto* idx = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, size_t(kGrid) * kGrid * 2));
        for (int j = 0; j < kGrid; ++j)
            for (int i = 0; i < kGrid; ++i) {
                const unsigned a = unsigned(j * (kGrid + 1) + i);
                unsigned* t = idx + 6 * (j * kGrid + i);
                t[0] = a;
                t[1] = a + 1;
                t[2] = a + kGrid + 2;
                t[3] = a;
                t[4] = a + kGrid + 2;
                t[5] = a + kGrid + 1;
            }
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(b.scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(b.scene);
    b.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    b.bytes = g_bytes.load();
    return b;
}

struct Rays {
    std::vector<glm::vec3> org, dir;
};

const Rays& rays() {
    static const Rays r = [] {
        Rays out;
        std::mt19937 rng(42);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        for (int i = 0; i < 1 << 16; ++i) {
            out.org.emplace_back(u(rng), 0.1f + 0.2f * u(rng), u(rng));
            const float z = 1.f - 2.f * u(rng), phi = 6.2831853f * u(rng), s = std::sqrt(1.f - z * z);
            out.dir.emplace_back(s * std::cos(phi), z, s * std::sin(phi));
        }
        return out;
    }();
    return r;
}

void trace(benchmark::State& state, bool quads, bool shadow) {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    const Built b = build(quads);
    const Rays& r = rays();
    size_t i = 0, hits = 0;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (auto _ : state) {
        const size_t k = i++ & (r.org.size() - 1);
        RTCRayHit rh{};
        rh.ray.org_x = r.org[k].x;
        rh.ray.org_y = r.org[k].y;
        rh.ray.org_z = r.org[k].z;
        rh.ray.dir_x = r.dir[k].x;
        rh.ray.dir_y = r.dir[k].y;
        rh.ray.dir_z = r.dir[k].z;
        rh.ray.tfar = shadow ? 0.5f : INFINITY;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        if (shadow) {
            rtcOccluded1(b.scene, &ctx, &rh.ray);
            hits += rh.ray.tfar < 0.f;
        } else {
            rtcIntersect1(b.scene, &ctx, &rh);
            hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    }
    benchmark::DoNotOptimize(hits);
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.counters["build_s"] = b.build_seconds;
    state.counters["bytes_per_quad"] = double(b.bytes) / (double(kGrid) * kGrid);
    rtcReleaseScene(b.scene);
    rtcReleaseDevice(b.device);
}

void BM_Intersect_Triangles(benchmark::State& s) { trace(s, false, false); }
void BM_Intersect_Quads(benchmark::State& s) { trace(s, true, false); }
void BM_Occluded_Triangles(benchmark::State& s) { trace(s, false, true); }
void BM_Occluded_Quads(benchmark::State& s) { trace(s, true, true); }
BENCHMARK(BM_Intersect_Triangles)->MinTime(1.0);
BENCHMARK(BM_Intersect_Quads)->MinTime(1.0);
BENCHMARK(BM_Occluded_Triangles)->MinTime(1.0);
BENCHMARK(BM_Occluded_Quads)->MinTime(1.0);

}  // namespace

BENCHMARK_MAIN();
