// tests/scene/test_texture_storage.cpp: textures kept as 8-bit codes in 4x4 tiles look up the same values as the
// floats they decode to, bit for bit, with the repeat wrap (i mod n for every size and index, uvs beyond the range
// of long long included); a grey mask keeps its levels as alpha.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cstring>

#include "core/frame/renderer.h"
#include "core/sampling/rng.h"
#include "core/scene/texture.h"
#include "support/scenes.h"

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
    // 4 bytes a texel, in 4x4 blocks: 7x5 texels pad to 8x8.
    EXPECT_EQ(coded.bytes(), size_t(8 * 8 * 4)) << "every texel is an 8-bit code: 4 bytes each";
    // Every one of the 256 codes in every channel is recognised.
    std::vector<vec4> all(256);
    for (int c = 0; c < 256; ++c)
        all[size_t(c)] =
            vec4(srgb_code_to_linear(c), srgb_code_to_linear(255 - c), srgb_code_to_linear(c), float(255 - c) / 255.f);
    EXPECT_EQ(Texture(16, 16, all).bytes(), all.size() * 4);
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
            EXPECT_TRUE(same_bits(a[c], r[c]))
                << "uv " << uv.x << "," << uv.y << " channel " << c << ": " << a[c] << " vs " << r[c];
            if (c < 3) {
                EXPECT_TRUE(same_bits(b[c], r[c])) << "float storage, uv " << uv.x << "," << uv.y;
            }
        }
    }
}

// The repeat wrap without divisions (wrap_texel_index: a mask for powers of two, fastmod below 2^32, the division
// beyond) is i mod n, for texture sizes from 1 to INT_MAX, indices of both signs up to and past 2^32 in magnitude.
TEST(TextureStorage, WrapIsTheModuloForEverySizeAndIndex) {
    std::vector<int> sizes;
    for (int n = 1; n <= 80; ++n) sizes.push_back(n);
    for (const int n : {94, 477, 640, 1021, 4095, 4096, 16383, 65535, 65537, (1 << 20) + 3, 2147483646, 2147483647})
        sizes.push_back(n);
    Pcg32 rng(9, 10);
    for (const int n : sizes) {
        const uint64_t magic = wrap_magic(n);
        std::vector<long long> indices;
        for (const long long base : {0ll, 1ll * n, 2ll * n, 7ll * n, 1ll << 31, (1ll << 32) - 1, 1ll << 32, 1ll << 40})
            for (long long d = -2; d <= 2; ++d) {
                indices.push_back(base + d);
                indices.push_back(-(base + d));
            }
        for (int k = 0; k < 2000; ++k) {
            const long long r = static_cast<long long>(rng.next_u32()) - (1ll << 31);
            indices.push_back(k % 2 ? r : r % (64ll * n));
        }
        for (const long long i : indices) {
            const auto expected = static_cast<size_t>(((i % n) + n) % n);
            ASSERT_EQ(wrap_texel_index(i, n, magic), expected) << "i = " << i << ", n = " << n;
        }
    }
}

// A finite uv beyond the range of long long (3e23 from a damaged glTF, found by fuzz_gltf) wraps as the modulo of
// its whole-number texel coordinate: lookups equal the reference computed with exact double arithmetic. (The cast to
// long long was undefined behaviour there; UBSan stops the ASan suite on it.)
TEST(TextureStorage, UvsBeyondTheRangeOfLongLongWrapAsTheModulo) {
    const int w = 7, h = 5;
    Pcg32 rng(11, 12);
    const std::vector<vec4> texels = [&] {
        std::vector<vec4> t(size_t(w) * size_t(h));
        for (vec4& v : t) v = vec4(rng.next_float(), rng.next_float(), rng.next_float(), 1.f);
        return t;
    }();
    const Texture tex(w, h, texels);
    auto wrap = [](double f, int n) {
        const double r = std::fmod(f, double(n));
        return static_cast<size_t>(r < 0 ? r + n : r);
    };
    for (const float u : {-3.3802e23f, 3.3802e23f, 1e30f, -1e30f, 9.3e18f, -9.3e18f, 4.8e37f, -4.8e37f}) {
        for (const float v : {0.25f, u}) {
            const vec4 got = tex.lookup(vec2(u, v));
            // Beyond 2^24 a texel coordinate is a whole float (its fraction is 0); the reference wraps it in
            // double, where fmod is exact, and blends the four texels as reference_lookup does.
            const float x = u * float(w) - 0.5f, y = (1.f - v) * float(h) - 0.5f;
            ASSERT_TRUE(std::isfinite(x) && std::isfinite(y));
            const float fx = std::floor(x), fy = std::floor(y), tx = x - fx, ty = y - fy;
            const size_t x0 = wrap(fx, w), x1 = (x0 + 1) % size_t(w), y0 = wrap(fy, h), y1 = (y0 + 1) % size_t(h);
            const size_t W = size_t(w);
            const vec4 ref = (1.f - ty) * ((1.f - tx) * texels[y0 * W + x0] + tx * texels[y0 * W + x1]) +
                             ty * ((1.f - tx) * texels[y1 * W + x0] + tx * texels[y1 * W + x1]);
            for (int c = 0; c < 4; ++c) EXPECT_TRUE(same_bits(got[c], ref[c])) << "u " << u << " v " << v << " c " << c;
        }
    }
}

// Random texels that are all 8-bit codes (colour sRGB, alpha linear), row-major.
std::vector<vec4> random_code_texels(int w, int h, Pcg32& rng) {
    std::vector<vec4> texels(size_t(w) * size_t(h));
    for (vec4& t : texels)
        t = vec4(srgb_code_to_linear(int(rng.next_u32() % 256)), srgb_code_to_linear(int(rng.next_u32() % 256)),
                 srgb_code_to_linear(int(rng.next_u32() % 256)), float(rng.next_u32() % 256) / 255.f);
    return texels;
}

// The codes are stored in 4x4 tiles (64-byte blocks): every size, even or odd, 1xN and Nx1 included, looks up what
// the row-major reference gives, bit for bit, in all four channels (alpha masks included), wrapping at every edge.
TEST(TextureStorage, TiledCodesLookUpAsTheRowMajorReference) {
    const int sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {2, 3}, {3, 3}, {4, 4}, {5, 7}, {8, 3}, {17, 9}, {33, 2}, {64, 65}};
    Pcg32 rng(5, 6);
    for (const auto& size : sizes) {
        const int w = size[0], h = size[1];
        const std::vector<vec4> texels = random_code_texels(w, h, rng);
        const Texture t(w, h, texels);
        const size_t padded = size_t((w + 3) / 4 * 4) * size_t((h + 3) / 4 * 4);
        ASSERT_EQ(t.bytes(), padded * 4) << w << "x" << h << ": kept as tiled codes";
        ASSERT_TRUE(t.has_alpha());
        // The row-major texels come back out.
        const std::vector<vec4> back = t.texels();
        ASSERT_EQ(back.size(), texels.size());
        for (size_t i = 0; i < texels.size(); ++i)
            for (int c = 0; c < 4; ++c) ASSERT_TRUE(same_bits(back[i][c], texels[i][c])) << w << "x" << h << " " << i;
        for (int i = 0; i < 3000; ++i) {
            const float span = i < 1000 ? 1.f : i < 2000 ? 3.f : 1e3f;
            vec2 uv((rng.next_float() - 0.3f) * span, (rng.next_float() - 0.3f) * span);
            // Texel centres and edges, the image's own edges (0 and 1) and one period outside them.
            if (i % 5 == 0)
                uv = vec2(float(int(rng.next_u32() % uint32_t(3 * w + 1)) - w) / float(2 * w),
                          float(int(rng.next_u32() % uint32_t(3 * h + 1)) - h) / float(2 * h));
            const vec4 a = t.lookup(uv), r = reference_lookup(texels, w, h, uv);
            for (int c = 0; c < 4; ++c)
                ASSERT_TRUE(same_bits(a[c], r[c])) << w << "x" << h << " uv " << uv.x << "," << uv.y << " channel " << c
                                                   << ": " << a[c] << " vs " << r[c];
        }
    }
}

// Where each texel goes in the tiles: inside a 4x4 block row-major, the blocks row-major, each block 16 codes.
TEST(TextureStorage, TiledIndexCoversEachPaddedSlotOnce) {
    for (const int w : {1, 3, 4, 5, 13}) {
        const size_t blocks = size_t(w + 3) / 4;
        const int h = 7;
        std::vector<int> seen(blocks * 2 * 16, 0);
        for (size_t y = 0; y < size_t(h); ++y)
            for (size_t x = 0; x < size_t(w); ++x) {
                const size_t i = Texture::tiled_index(x, y, blocks);
                ASSERT_LT(i, seen.size());
                ++seen[i];
                EXPECT_EQ(i / 16, (y / 4) * blocks + x / 4) << "the block of " << x << "," << y;
            }
        for (const int n : seen) EXPECT_LE(n, 1);
    }
}

// A mask (map_d) decoded from a grey image keeps its grey levels as alpha through the tiles.
TEST(TextureStorage, TiledAlphaMaskFromAGreyImage) {
    const int w = 5, h = 3;
    std::vector<uint32_t> codes(size_t(w * h));
    for (size_t i = 0; i < codes.size(); ++i) codes[i] = 0x00ffffffu | uint32_t(i * 17) << 24;
    const Texture t(w, h, codes);
    EXPECT_TRUE(t.has_alpha());
    std::vector<vec4> decoded(codes.size());
    for (size_t i = 0; i < codes.size(); ++i) decoded[i] = vec4(vec3(srgb_code_to_linear(255)), float(i * 17) / 255.f);
    Pcg32 rng(8, 9);
    for (int i = 0; i < 500; ++i) {
        const vec2 uv(rng.next_float() * 3.f - 1.f, rng.next_float() * 3.f - 1.f);
        EXPECT_TRUE(same_bits(t.lookup(uv).w, reference_lookup(decoded, w, h, uv).w)) << uv.x << "," << uv.y;
    }
}

}  // namespace
}  // namespace pv
