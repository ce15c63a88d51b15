// tests/fuzz/fuzz_image.cpp: libFuzzer entry point over pathview's image loaders (Texture::decode): format sniffing,
// the declared-size budget, libjpeg-turbo, libpng and libwebp (JPEG, PNG, WebP), the Radiance RLE walk before
// stb_image, stb_image's TGA/BMP/PSD/GIF/PNM/HDR decoders, and the EXR header walk before OpenEXR. Bad input must end
// in pv::Error or a texture, in bounded time and memory (libFuzzer's -timeout and -rss_limit_mb), never a crash, a
// sanitizer report or a non-finite texel. Seeds and the issue-15 reproducers: tests/fuzz/corpus-image
// (tests/fuzz/make_corpus.py).
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/base/error.h"
#include "core/image/image_io.h"
#include "core/scene/texture.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // 4 megapixels: large enough for every decoder's paths, small enough for thousands of runs a second.
    pv::set_image_limits(pv::ImageLimits{4'000'000});
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > (1u << 20)) return 0;
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    for (bool alpha : {false, true}) {
        pv::Texture t;
        try {
            t = pv::Texture::decode(bytes, "fuzz.img", alpha);
        } catch (const pv::Error&) {
            return 0;
        }
        if (t.width() <= 0 || t.height() <= 0 || uint64_t(t.width()) * uint64_t(t.height()) > 4'000'000u) std::abort();
        for (float u : {0.f, 0.37f, 0.99f}) {
            const pv::vec4 v = t.lookup(pv::vec2(u, 1.f - u));
            if (!std::isfinite(v.x + v.y + v.z + v.w)) std::abort();
        }
    }
    return 0;
}
