// microbench/texture_wrap.cpp: the texel address of a bilinear lookup (Texture::prefetch) on tiled uvs, where the
// repeat wrap takes every lookup: the division-free wrap (wrap_texel_index) against the 64-bit modulo it replaced,
// for a texture size that is not a power of two (Sponza's 640x477) and one that is (512x512), and the prefetch
// itself on such uvs. A dependent chain (each uv from the last result) measures latency, as a path's lookup sees it.
// Run: build/microbench/pathview_microbench_texture
#include <benchmark/benchmark.h>

#include <cmath>

#include "core/sampling/rng.h"
#include "core/scene/texture.h"

namespace {

// The wrap before: i mod n by a 64-bit division when i is out of range (mask and fastmod came later).
size_t wrap_modulo(long long i, int n) {
    if (i >= 0 && i < n) return static_cast<size_t>(i);
    const long long r = i % n;
    return static_cast<size_t>(r < 0 ? r + n : r);
}

// Texel columns of uvs spread over [-4, 8) (a floor tiled a dozen times), as a dependent chain.
template <bool kModulo>
void BM_Wrap(benchmark::State& state) {
    const int n = int(state.range(0));
    const uint64_t magic = pv::wrap_magic(n);
    pv::Pcg32 rng(1, 2);
    std::vector<long long> is(4096);
    for (long long& i : is) i = static_cast<long long>(std::floor((rng.next_float() * 12.f - 4.f) * float(n)));
    size_t k = 0, acc = 0;
    for (auto _ : state) {
        const long long i = is[k++ & 4095] + static_cast<long long>(acc & 1);
        const size_t x = kModulo ? wrap_modulo(i, n) : pv::wrap_texel_index(i, n, magic);
        acc += x;
        benchmark::DoNotOptimize(acc);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK_TEMPLATE(BM_Wrap, true)->Arg(640)->Arg(477)->Arg(512);
BENCHMARK_TEMPLATE(BM_Wrap, false)->Arg(640)->Arg(477)->Arg(512);

// Texture::prefetch (the footprint of four texels and their prefetch) at tiled uvs, 640x477 and 512x512.
void BM_Prefetch(benchmark::State& state) {
    const int w = int(state.range(0)), h = int(state.range(1));
    pv::Pcg32 rng(3, 4);
    std::vector<uint32_t> codes(size_t(w) * size_t(h));
    for (uint32_t& c : codes) c = rng.next_u32() | 0xff000000u;
    const pv::Texture t(w, h, std::move(codes));
    std::vector<pv::vec2> uvs(4096);
    for (pv::vec2& uv : uvs) uv = pv::vec2(rng.next_float() * 12.f - 4.f, rng.next_float() * 12.f - 4.f);
    size_t k = 0;
    float carry = 0.f;
    for (auto _ : state) {
        const pv::TexelFootprint fp = t.prefetch(uvs[k++ & 4095] + pv::vec2(carry));
        carry = fp.tx * 1e-30f;  // 0, but the next uv waits for this footprint
        benchmark::DoNotOptimize(fp);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Prefetch)->Args({640, 477})->Args({512, 512});

}  // namespace

BENCHMARK_MAIN();
