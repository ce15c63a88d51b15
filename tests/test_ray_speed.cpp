// tests/test_ray_speed.cpp: what the ray-speed work (issue 13, docs/ray-speed.md) must not change: a texture kept
// as 8-bit codes looks up the same values as the floats they decode to, with the same repeat wrap at any uv.
#include "core/rng.h"
#include "core/texture.h"

#include <gtest/gtest.h>

#include <cstring>

namespace pv {
namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Bilinear lookup with repeat wrap written out plainly (two modulo operations per coordinate), as Texture::lookup
// computed it before it skipped the divisions.
vec4 reference_lookup(const std::vector<vec4>& t, int w, int h, vec2 uv) {
    const float x = uv.x * float(w) - 0.5f, y = (1.f - uv.y) * float(h) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float tx = x - fx, ty = y - fy;
    auto wrap = [](long long i, int n) { return static_cast<size_t>(((i % n) + n) % n); };
    const long long ix = static_cast<long long>(fx), iy = static_cast<long long>(fy);
    const size_t x0 = wrap(ix, w), x1 = wrap(ix + 1, w), y0 = wrap(iy, h), y1 = wrap(iy + 1, h);
    const size_t W = size_t(w);
    return (1.f - ty) * ((1.f - tx) * t[y0 * W + x0] + tx * t[y0 * W + x1]) +
           ty * ((1.f - tx) * t[y1 * W + x0] + tx * t[y1 * W + x1]);
}

TEST(TextureStorage, EightBitCodesLookUpAsTheFloatsTheyDecodeTo) {
    const int w = 7, h = 5;  // odd sizes: wrapping is not a bit mask
    Pcg32 rng(3, 4);
    std::vector<vec4> texels(size_t(w) * size_t(h));
    for (vec4& t : texels)
        t = vec4(srgb_code_to_linear(int(rng.next_u32() % 256)), srgb_code_to_linear(int(rng.next_u32() % 256)),
                 srgb_code_to_linear(int(rng.next_u32() % 256)), float(rng.next_u32() % 256) / 255.f);
    const Texture coded(w, h, texels);
    EXPECT_EQ(coded.bytes(), texels.size() * 4) << "every texel is an 8-bit code: 4 bytes each";
    // The same colours with one alpha that no byte gives: kept as floats.
    std::vector<vec4> odd = texels;
    odd[0].w = 0.3f;
    const Texture floats(w, h, odd);
    EXPECT_EQ(floats.bytes(), texels.size() * sizeof(vec4));

    for (int i = 0; i < 4000; ++i) {
        // Inside [0, 1), around it, far outside (negative and positive), and exactly on texel edges.
        const float span = i < 1000 ? 1.f : i < 2000 ? 4.f : 2e4f;
        vec2 uv((rng.next_float() - 0.25f) * span, (rng.next_float() - 0.25f) * span);
        if (i % 7 == 0) uv = vec2(float(i % w) / float(w), float(i % h) / float(h));
        const vec4 a = coded.lookup(uv), b = floats.lookup(uv), r = reference_lookup(texels, w, h, uv);
        for (int c = 0; c < 4; ++c) {
            EXPECT_TRUE(same_bits(a[c], r[c])) << "uv " << uv.x << "," << uv.y << " channel " << c << ": " << a[c]
                                               << " vs " << r[c];
            if (c < 3) {
                EXPECT_TRUE(same_bits(b[c], r[c])) << "float storage, uv " << uv.x << "," << uv.y;
            }
        }
    }
}

}  // namespace
}  // namespace pv
