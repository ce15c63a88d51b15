// tests/sampling/test_sobol.cpp: the Owen-scrambled padded Sobol sampler (stratification, decorrelation across pixels,
// determinism): every 2D draw of the first 2^m even (or odd) samples of a pixel is a (0,m,2)-net (pbrt-v4's
// ElementaryIntervals test), 1D draws are stratified, the even and odd halves are uncorrelated, values are never 1.0,
// and the values depend only on (pixel, index, seed, dimension).
// Test kinds: unit
#include <gtest/gtest.h>

#include <vector>

#include "core/sampling/sampler.h"
#include "core/sampling/sobol.h"

namespace pv {
namespace {

// True if each of the 2^m elementary intervals of every shape 2^a x 2^(m-a) holds exactly one point.
bool is_02_net(const std::vector<vec2>& pts, int m) {
    for (int a = 0; a <= m; ++a) {
        const int nx = 1 << a, ny = 1 << (m - a);
        std::vector<int> count(size_t(nx) * size_t(ny), 0);
        for (const vec2& p : pts) {
            const int ix = static_cast<int>(p.x * float(nx)), iy = static_cast<int>(p.y * float(ny));
            if (ix < 0 || ix >= nx || iy < 0 || iy >= ny) return false;
            count[size_t(iy) * size_t(nx) + size_t(ix)]++;
        }
        for (int c : count)
            if (c != 1) return false;
    }
    return true;
}

// Skips `skip_2d` (2D, 1D) draw pairs, then returns the next 2D draw of samples parity, parity + 2, ...
// (n samples of one half of a pixel).
std::vector<vec2> draw_2d(SamplerKind kind, uvec2 pixel, uint32_t seed, int n, int skip_2d, uint32_t parity = 0) {
    Sampler s(seed, kind);
    std::vector<vec2> out;
    for (int i = 0; i < n; ++i) {
        s.start(pixel, 2 * uint32_t(i) + parity);
        for (int k = 0; k < skip_2d; ++k) {
            s.get2d();
            s.get1d();
        }
        out.push_back(s.get2d());
    }
    return out;
}

TEST(Sobol, Dim1MatchesDirectionNumbers) {
    // Dimension 1 of Sobol in index (not Gray-code) order: XORs of the direction numbers 1/2, 3/4, 5/8.
    const double expect[8] = {0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
    for (uint32_t i = 0; i < 8; ++i) EXPECT_DOUBLE_EQ(double(sobol_dim1(i)) * 0x1p-32, expect[i]) << i;
    for (uint32_t i = 0; i < 8; ++i)
        EXPECT_DOUBLE_EQ(double(sobol_dim0(i)) * 0x1p-32, i == 0 ? 0.0 : double(reverse_bits32(i)) * 0x1p-32);
}

TEST(Sobol, Dim1ReversedMatchesTheGeneratorMatrix) {
    // The shift-and-mask form the sampler uses equals the generator-matrix tables, bit-reversed, on every low index
    // and on a spread of 32-bit ones.
    for (uint32_t i = 0; i < (1u << 20); ++i) ASSERT_EQ(sobol_dim1_reversed(i), reverse_bits32(sobol_dim1(i))) << i;
    for (uint64_t i = 0; i < (1ull << 32); i += 2654435761ull / 1024)
        ASSERT_EQ(sobol_dim1_reversed(uint32_t(i)), reverse_bits32(sobol_dim1(uint32_t(i)))) << i;
}

TEST(Sobol, OwenScrambleIsABijectionOnEveryPrefix) {
    // Nested uniform scrambling maps each dyadic interval onto a dyadic interval of the same size: on the top
    // 8 bits it must be a permutation of 0..255.
    for (uint32_t seed : {0u, 1u, 0xdeadbeefu, 0x12345678u}) {
        std::vector<int> seen(256, 0);
        for (uint32_t v = 0; v < 256; ++v) seen[owen_scramble(v << 24, seed) >> 24]++;
        for (int c : seen) EXPECT_EQ(c, 1);
    }
}

TEST(Sobol, ElementaryIntervals2D) {
    for (int m = 0; m <= 10; ++m)
        for (uvec2 pixel : {uvec2(0, 0), uvec2(17, 3), uvec2(511, 400)})
            for (int dim = 0; dim < 4; ++dim)
                for (uint32_t parity : {0u, 1u})
                    EXPECT_TRUE(is_02_net(draw_2d(SamplerKind::Sobol, pixel, 7, 1 << m, dim, parity), m))
                        << "m=" << m << " pixel=" << pixel.x << "," << pixel.y << " draw=" << dim << " half=" << parity;
}

TEST(Sobol, Stratified1D) {
    for (int m = 0; m <= 10; ++m) {
        const int n = 1 << m;
        for (int draw = 0; draw < 3; ++draw)
            for (uint32_t parity : {0u, 1u}) {
                Sampler s(3, SamplerKind::Sobol);
                std::vector<int> count(size_t(n), 0);
                for (int i = 0; i < n; ++i) {
                    s.start(uvec2(5, 9), 2 * uint32_t(i) + parity);
                    for (int k = 0; k < draw; ++k) s.get1d();
                    count[size_t(s.get1d() * float(n))]++;
                }
                for (int c : count) ASSERT_EQ(c, 1) << "m=" << m << " draw=" << draw << " half=" << parity;
            }
    }
}

TEST(Sobol, IndependentSamplerIsNotANet) {
    // Sanity check of the net test itself: 256 independent points are (almost surely) not a (0,8,2)-net.
    EXPECT_FALSE(is_02_net(draw_2d(SamplerKind::Independent, uvec2(1, 2), 0, 256, 0), 8));
}

TEST(Sobol, NeverOne) {
    // The largest fixed-point value and many random indices: every float is < 1.
    EXPECT_LT(fixed_to_float(0xffffffffu), 1.f);
    for (SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Independent}) {
        Sampler s(0xffffffffu, kind);
        float hi = 0.f;
        for (uint32_t i = 0; i < 20000; ++i) {
            s.start(uvec2(i * 7919u, i), i * 2654435761u);
            for (int d = 0; d < 8; ++d) {
                const vec2 u = s.get2d();
                hi = std::max(hi, std::max(std::max(u.x, u.y), s.get1d()));
                ASSERT_GE(u.x, 0.f);
                ASSERT_GE(u.y, 0.f);
            }
        }
        EXPECT_LT(hi, 1.f);
    }
}

TEST(Sobol, DeterministicPerPixelIndexSeed) {
    auto values = [](uint32_t seed, uvec2 pixel, uint32_t index) {
        Sampler s(seed, SamplerKind::Sobol);
        s.start(pixel, index);
        std::vector<float> v;
        for (int d = 0; d < 6; ++d) {
            const vec2 u = s.get2d();
            v.insert(v.end(), {u.x, u.y, s.get1d()});
        }
        return v;
    };
    // Same inputs, different order of calls in between: same values.
    const auto a = values(1, uvec2(3, 4), 5);
    (void)values(9, uvec2(100, 4), 77);
    EXPECT_EQ(a, values(1, uvec2(3, 4), 5));
    EXPECT_NE(a, values(2, uvec2(3, 4), 5));
    EXPECT_NE(a, values(1, uvec2(4, 3), 5));
    EXPECT_NE(a, values(1, uvec2(3, 4), 6));
}

TEST(Sobol, PixelsAreDecorrelated) {
    // Sample 0 of neighbouring pixels must not share values (each pixel has its own shuffle and scramble).
    Sampler s(0, SamplerKind::Sobol);
    double sx = 0, sy = 0, sxy = 0, sxx = 0, syy = 0;
    const int n = 4096;
    for (int i = 0; i < n; ++i) {
        s.start(uvec2(uint32_t(i), 0), 0);
        const float a = s.get1d();
        s.start(uvec2(uint32_t(i) + 1, 0), 0);
        const float b = s.get1d();
        sx += a, sy += b, sxy += a * b, sxx += a * a, syy += b * b;
    }
    const double cov = sxy / n - sx / n * sy / n;
    const double r = cov / std::sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
    EXPECT_LT(std::fabs(r), 4.0 / std::sqrt(double(n)));
}

TEST(Sobol, EvenAndOddHalvesAreUncorrelated) {
    // The film's error estimate compares the even and odd half means, so they must be independent: for a 1D and a
    // 2D draw, the correlation between samples 2k and 2k+1 of a pixel (over many pixels and k) must be that of
    // independent values, |r| < 4 / sqrt(n). One net over all samples fails this: 2k and 2k+1 then fall into
    // opposite halves of [0, 1) (r about -0.75).
    Sampler s(11, SamplerKind::Sobol);
    for (int draw = 0; draw < 3; ++draw) {
        double sx = 0, sy = 0, sxy = 0, sxx = 0, syy = 0;
        int n = 0;
        for (uint32_t px = 0; px < 512; ++px)
            for (uint32_t k = 0; k < 8; ++k) {
                float v[2];
                for (uint32_t parity : {0u, 1u}) {
                    s.start(uvec2(px, 7), 2 * k + parity);
                    const vec2 u2 = s.get2d();
                    const float u1 = s.get1d();
                    v[parity] = draw == 0 ? u2.x : draw == 1 ? u2.y : u1;
                }
                sx += v[0], sy += v[1], sxy += double(v[0]) * v[1], sxx += double(v[0]) * v[0],
                    syy += double(v[1]) * v[1];
                ++n;
            }
        const double cov = sxy / n - sx / n * sy / n;
        const double r = cov / std::sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
        EXPECT_LT(std::fabs(r), 4.0 / std::sqrt(double(n))) << "draw " << draw;
    }
}

TEST(Sobol, ParseAndName) {
    EXPECT_EQ(parse_sampler("sobol"), SamplerKind::Sobol);
    EXPECT_EQ(parse_sampler("independent"), SamplerKind::Independent);
    EXPECT_FALSE(parse_sampler("halton").has_value());
    EXPECT_STREQ(sampler_name(SamplerKind::Sobol), "sobol");
}

}  // namespace
}  // namespace pv
