// tests/render/test_shading_shortcuts.cpp: per-ray shortcuts give the same bits as the code they replace:
// cell_to_unit's float path for power-of-two cell counts against the double division, the one-column Distribution2D
// against its alias table, and Texture::lookup from a prefetched footprint against the plain lookup. Fixed seeds.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "core/sampling/distribution.h"
#include "core/sampling/rng.h"
#include "core/scene/texture.h"

namespace pv {
namespace {

uint32_t bits(float x) {
    uint32_t b = 0;
    std::memcpy(&b, &x, sizeof b);
    return b;
}

float from_bits(uint32_t b) {
    float x = 0.f;
    std::memcpy(&x, &b, sizeof x);
    return x;
}

// Offsets in [0, 1) of every kind: 24-bit grid values (what the samplers give), any float (random bit patterns
// over all binades down to 2^-40), and the float neighbours of the rounding midpoints of cell + offset.
std::vector<float> offsets_for(size_t cell, Pcg32& rng) {
    std::vector<float> out = {0.f, kOneMinusEpsilon, 0.5f, 0x1p-24f, 0x1p-40f};
    for (int i = 0; i < 64; ++i) out.push_back(rng.next_float());
    for (int i = 0; i < 64; ++i) {
        const int e = 87 + int(rng.next_u32() % 39);  // biased exponent: 2^-40 .. 2^-2
        out.push_back(from_bits(uint32_t(e) << 23 | (rng.next_u32() & 0x7fffffu)));
    }
    // Midpoints of the float grid around cell + offset: spacing ulp(cell + offset) / 2.
    const float c = float(cell);
    const float ulp = cell == 0 ? 0x1p-24f : std::nextafter(c + 0.5f, 2.f * c + 2.f) - (c + 0.5f);
    for (int i = 0; i < 16; ++i) {
        const float mid = (float(rng.next_u32() % 1024) + 0.5f) * ulp;
        if (!(mid < 1.f)) continue;
        out.push_back(mid);
        out.push_back(std::nextafter(mid, 0.f));
        out.push_back(std::nextafter(mid, 1.f));
    }
    return out;
}

TEST(ShadingShortcuts, CellToUnitFloatPathMatchesTheDoubleDivision) {
    Pcg32 rng(11, 3);
    size_t checked = 0;
    // Every power of two to 2^24 (the float path), and other counts (the reference path: the float formula would
    // round there, so these fail if the power-of-two test is dropped).
    std::vector<size_t> counts = {3, 5, 17, 1000, 4095, (size_t(1) << 24) + 1};
    for (size_t n = 1; n <= (size_t(1) << 24); n *= 2) counts.push_back(n);
    for (const size_t n : counts) {
        std::vector<size_t> cells = {0, n - 1, n / 2, n / 3};
        for (int i = 0; i < 8; ++i) cells.push_back(size_t(rng.next_u32()) % n);
        for (const size_t cell : cells) {
            for (const float offset : offsets_for(cell, rng)) {
                ASSERT_EQ(bits(cell_to_unit(cell, offset, n)), bits(cell_to_unit_reference(cell, offset, n)))
                    << "n " << n << " cell " << cell << " offset " << offset;
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 10000u);
}

// The default sky's shape: one column, many rows. sample() skips the row's alias table; x, the texel and the pdf
// are what the table gives (x = offset = u.x, texel = row), y the marginal's sample.
TEST(ShadingShortcuts, OneColumnDistributionMatchesItsAliasTable) {
    for (const int h : {1, 7, 512}) {
        std::vector<float> f(static_cast<size_t>(h));
        Pcg32 rng(5, uint64_t(h));
        for (float& x : f) x = 0.05f + rng.next_float();
        const Distribution2D dist(f, 1, h);
        const Distribution1D marginal(f);  // a one-texel row's integral is its weight
        const AliasSlot one_slot;          // a one-cell table: threshold 1, alias 0
        for (int s = 0; s < 20000; ++s) {
            const vec2 u(rng.next_float(), rng.next_float());
            float pdf = 0.f, pdf_y = 0.f, offset = -1.f;
            size_t texel = 99, row = 98;
            const vec2 p = dist.sample(u, &pdf, &texel);
            const float y = marginal.sample(u.y, &pdf_y, &row);
            ASSERT_EQ(sample_alias_table(&one_slot, 1, u.x, &offset), 0u);
            ASSERT_EQ(bits(p.x), bits(cell_to_unit_reference(0, offset, 1))) << "h " << h << " u " << u.x;
            ASSERT_EQ(bits(p.y), bits(y));
            ASSERT_EQ(texel, row);
            ASSERT_EQ(pdf, dist.pdf_cell(row));
        }
    }
}

// lookup(prefetch(uv)) is lookup(uv), bit for bit, for 8-bit (tiled) and float storage, odd sizes, uvs outside
// [0, 1) (wrapping), on texel centres and edges, and non-finite uvs (texel 0); an empty texture gives 1.
TEST(ShadingShortcuts, LookupFromThePrefetchedFootprintIsTheLookup) {
    Pcg32 rng(3, 9);
    const int w = 13, h = 7;
    std::vector<uint32_t> codes(size_t(w) * h);
    std::vector<vec4> texels(codes.size());
    for (size_t i = 0; i < codes.size(); ++i) {
        codes[i] = rng.next_u32();
        texels[i] = vec4(rng.next_float(), rng.next_float(), 4.f * rng.next_float(), rng.next_float());
    }
    const Texture coded(w, h, codes), floats(w, h, texels);
    std::vector<vec2> uvs = {
        vec2(0.f),           vec2(1.f), vec2(-3.25f, 7.5f), vec2(0.5f / w, 0.5f / h), vec2(std::nanf(""), 0.5f),
        vec2(0.5f, INFINITY)};
    for (int i = 0; i < 5000; ++i) uvs.push_back(vec2(6.f * rng.next_float() - 3.f, 6.f * rng.next_float() - 3.f));
    for (const Texture* t : {&coded, &floats}) {
        for (const vec2 uv : uvs) {
            const vec4 a = t->lookup(uv), b = t->lookup(t->prefetch(uv));
            for (int c = 0; c < 4; ++c) ASSERT_EQ(bits(a[c]), bits(b[c])) << "uv " << uv.x << ", " << uv.y;
        }
    }
    const Texture empty;
    EXPECT_EQ(empty.lookup(empty.prefetch(vec2(0.3f))), vec4(1.f));
}

}  // namespace
}  // namespace pv
