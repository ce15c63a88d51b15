// tests/fuzz/fuzz_partial.cpp: libFuzzer entry point over partial-render EXRs (core/partial/partial.h) through merge's
// reader: the EXR header walk and image budget (read_exr_guarded), the identity attributes, sample ranges,
// channels, the size for the file, the block-wise pixel read and its checks, and the merge's sums. Bad input must
// end in pv::Error, never a crash or a sanitizer report; a part that is accepted must give a finite film (mean,
// error estimate) that writes and reads back bit for bit. Seeds: tests/fuzz/corpus-partial (valid parts written by
// `pathview render --samples` and `pathview merge`, see tests/fuzz/CMakeLists.txt).
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/base/error.h"
#include "core/image/image_io.h"
#include "core/partial/partial.h"
#include "core/partial/partial_merge.h"

namespace {
std::string g_in, g_out;  // per-process files: merge's reader reads paths
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // 4 megapixels: large enough for every path of the reader, small enough for many runs a second.
    pv::set_image_limits(pv::ImageLimits{4'000'000});
    const std::string dir = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    g_in = dir + "/pv-fuzz-partial-" + std::to_string(::getpid()) + ".exr";
    g_out = dir + "/pv-fuzz-partial-" + std::to_string(::getpid()) + "-out.exr";
    std::atexit([] {
        std::remove(g_in.c_str());
        std::remove(g_out.c_str());
    });
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > (1u << 20)) return 0;
    FILE* f = std::fopen(g_in.c_str(), "wb");
    if (!f) std::abort();
    if (size && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
    pv::PartialRender merged;
    try {
        merged = pv::merge_partial_files({g_in});
    } catch (const pv::Error&) {
        return 0;
    }
    // Accepted: every statistic is finite, and the part round-trips exactly.
    if (!std::isfinite(merged.film.estimated_rel_mse())) std::abort();
    for (float v : merged.film.mean().rgb)
        if (!std::isfinite(v) || v < 0.f) std::abort();
    for (float v : merged.film.variance_of_mean().rgb)
        if (!std::isfinite(v)) std::abort();
    pv::write_partial(g_out, merged);
    const pv::PartialRender back = pv::read_partial(g_out);
    const auto& a = merged.film.pixels();
    const auto& b = back.film.pixels();
    if (a.size() != b.size() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) != 0) std::abort();
    if (pv::format_ranges(back.ranges) != pv::format_ranges(merged.ranges)) std::abort();
    return 0;
}
