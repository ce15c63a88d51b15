// tests/scene/test_texture_wrap.cpp: the wrap modes of core/scene/texture.h (glTF's samplers: repeat, clamp to edge,
// mirrored repeat, per axis). Each mode's bilinear lookup equals a reference written out plainly (double arithmetic,
// the OpenGL definitions of the modes) at uvs inside [0, 1], just outside, negative, far away and beyond the range of
// long long, for 8-bit-code and float storage, odd and power-of-two sizes, every pair of modes on the two axes.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "core/sampling/rng.h"
#include "core/scene/texture.h"

namespace pv {
namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

constexpr TextureWrap kModes[] = {TextureWrap::Repeat, TextureWrap::ClampToEdge, TextureWrap::MirroredRepeat};

// The texel indices of the bilinear pair (i, i + 1) along an axis of n texels, i a whole number, as OpenGL defines
// the modes. Residues in double, where fmod is exact, so that i beyond 2^53 (where i + 1 == i) still pairs i's
// residue with the next one.
std::pair<size_t, size_t> reference_pair(double i, int n, TextureWrap mode) {
    if (mode == TextureWrap::ClampToEdge) {
        auto clamp = [&](double k) { return size_t(k < 0.0 ? 0.0 : k > n - 1 ? n - 1 : k); };
        return {clamp(i), clamp(i + 1.0)};
    }
    const double period = mode == TextureWrap::Repeat ? n : 2.0 * n;
    double r0 = std::fmod(i, period);
    if (r0 < 0.0) r0 += period;
    const double r1 = std::fmod(r0 + 1.0, period);
    auto mirror = [&](double k) { return size_t(mode == TextureWrap::Repeat || k < n ? k : 2.0 * n - 1.0 - k); };
    return {mirror(r0), mirror(r1)};
}

vec4 reference_lookup(const std::vector<vec4>& t, int w, int h, TextureWrap ws, TextureWrap wt, vec2 uv) {
    const float x = uv.x * float(w) - 0.5f, y = (1.f - uv.y) * float(h) - 0.5f;  // texel centres; row 0 on top
    if (!std::isfinite(x) || !std::isfinite(y)) return t[0];  // past float's range: texel 0 (texture.h)
    const float fx = std::floor(x), fy = std::floor(y);
    const float tx = x - fx, ty = y - fy;
    const auto [x0, x1] = reference_pair(fx, w, ws);
    const auto [y0, y1] = reference_pair(fy, h, wt);
    const size_t W = size_t(w);
    return (1.f - ty) * ((1.f - tx) * t[y0 * W + x0] + tx * t[y0 * W + x1]) +
           ty * ((1.f - tx) * t[y1 * W + x0] + tx * t[y1 * W + x1]);
}

std::vector<float> test_coordinates(Pcg32& rng) {
    std::vector<float> c = {0.f,     0.25f,   0.5f,     0.999f,     1.f,         1.001f,   -0.001f, -0.5f,   -1.f,
                            -1.75f,  2.3f,    3.5f,     -7.1f,      100.37f,     -100.37f, 1e4f,    -2.5e4f, 1e7f,
                            -3.3e7f, 9.3e18f, -9.3e18f, 3.3802e23f, -3.3802e23f, 1e30f,    -1e30f,  4.8e37f, -4.8e37f};
    for (int k = 0; k < 60; ++k) c.push_back((rng.next_float() - 0.4f) * (k < 30 ? 3.f : 300.f));
    return c;
}

// Every pair of modes, code and float storage, sizes odd, even and powers of two (1 is all edges).
TEST(TextureWrap, EveryModeOnEachAxisLooksUpAsThePlainReference) {
    Pcg32 rng(21, 22);
    const std::vector<float> coords = test_coordinates(rng);
    for (const auto& [w, h] : {std::pair{7, 5}, std::pair{8, 4}, std::pair{1, 3}, std::pair{6, 1}, std::pair{13, 16}}) {
        std::vector<vec4> codes(size_t(w) * size_t(h)), floats(codes.size());
        for (size_t i = 0; i < codes.size(); ++i) {
            codes[i] =
                vec4(srgb_code_to_linear(int(rng.next_u32() % 256)), srgb_code_to_linear(int(rng.next_u32() % 256)),
                     srgb_code_to_linear(int(rng.next_u32() % 256)), float(rng.next_u32() % 256) / 255.f);
            floats[i] = vec4(rng.next_float(), rng.next_float(), rng.next_float(), rng.next_float());
        }
        for (const std::vector<vec4>* texels : {&codes, &floats}) {
            Texture t(w, h, *texels);
            ASSERT_EQ(t.bytes() == texels->size() * sizeof(vec4), texels == &floats) << "both storages are tested";
            for (const TextureWrap ws : kModes)
                for (const TextureWrap wt : kModes) {
                    t.set_wrap(ws, wt);
                    ASSERT_EQ(t.wrap_s(), ws);
                    ASSERT_EQ(t.wrap_t(), wt);
                    int failures = 0;
                    for (const float u : coords)
                        for (const float v : coords) {
                            const vec2 uv(u, v);
                            const vec4 got = t.lookup(uv), ref = reference_lookup(*texels, w, h, ws, wt, uv);
                            const vec4 via_prefetch = t.lookup(t.prefetch(uv));
                            for (int c = 0; c < 4; ++c)
                                if (!same_bits(got[c], ref[c]) || !same_bits(via_prefetch[c], got[c])) {
                                    if (++failures <= 5)
                                        ADD_FAILURE()
                                            << w << "x" << h << " modes " << int(ws) << "," << int(wt) << " uv " << u
                                            << "," << v << " channel " << c << ": " << got[c] << " vs " << ref[c];
                                }
                        }
                    EXPECT_EQ(failures, 0) << w << "x" << h << " modes " << int(ws) << "," << int(wt);
                }
        }
    }
}

// What the modes mean, on a 2x1 texture (black, white) at texel centres: repeat, clamp and mirror differ where
// they should.
TEST(TextureWrap, ModesDifferAsOpenGLDefinesThem) {
    Texture t(2, 1, std::vector<vec4>{vec4(0.f, 0.f, 0.f, 1.f), vec4(1.f)});
    auto at = [&](TextureWrap m, float u) {
        t.set_wrap(m, TextureWrap::Repeat);
        return t.lookup(vec2(u, 0.5f)).x;
    };
    // Texel centres at u = 0.25 (black) and 0.75 (white); one texel further on each side.
    EXPECT_EQ(at(TextureWrap::Repeat, -0.25f), 1.f);
    EXPECT_EQ(at(TextureWrap::Repeat, 1.25f), 0.f);
    EXPECT_EQ(at(TextureWrap::ClampToEdge, -0.25f), 0.f);
    EXPECT_EQ(at(TextureWrap::ClampToEdge, 1.25f), 1.f);
    EXPECT_EQ(at(TextureWrap::ClampToEdge, -1e30f), 0.f);
    EXPECT_EQ(at(TextureWrap::ClampToEdge, 1e30f), 1.f);
    EXPECT_EQ(at(TextureWrap::MirroredRepeat, -0.25f), 0.f);  // mirrored about u = 0: black again
    EXPECT_EQ(at(TextureWrap::MirroredRepeat, 1.25f), 1.f);   // mirrored about u = 1: white again
    EXPECT_EQ(at(TextureWrap::MirroredRepeat, 1.75f), 0.f);   // then black
    EXPECT_EQ(at(TextureWrap::MirroredRepeat, 2.25f), 0.f);   // period 2
    EXPECT_EQ(at(TextureWrap::MirroredRepeat, -0.75f), 1.f);
    // The default is repeat, and a copy keeps its modes.
    const Texture fresh(2, 1, std::vector<vec4>{vec4(0.f, 0.f, 0.f, 1.f), vec4(1.f)});
    EXPECT_EQ(fresh.wrap_s(), TextureWrap::Repeat);
    EXPECT_EQ(fresh.wrap_t(), TextureWrap::Repeat);
    t.set_wrap(TextureWrap::MirroredRepeat, TextureWrap::ClampToEdge);
    const Texture copy = t;
    EXPECT_EQ(copy.wrap_s(), TextureWrap::MirroredRepeat);
    EXPECT_EQ(copy.wrap_t(), TextureWrap::ClampToEdge);
}

}  // namespace
}  // namespace pv
