// tests/base/test_unit.cpp: unit tests of the pieces: warps (domain, pdf normalisation), frames, the RNG and sampler
// (never 1.0, determinism), EXR round trip and write failures. (Thread-count determinism: test_threading.cpp.)
// Test kinds: unit; statistical: Chi2Rng
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "core/base/error.h"
#include "core/base/math.h"
#include "core/frame/renderer.h"
#include "core/image/image_io.h"
#include "core/sampling/rng.h"
#include "core/sampling/sampler.h"
#include "core/sampling/warp.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- warps

TEST(Warp, SamplesLandInTheirDomain) {
    Pcg32 rng(7, 3);
    for (int i = 0; i < 200000; ++i) {
        const vec2 u(rng.next_float(), rng.next_float());
        const vec2 d = square_to_disk_concentric(u);
        EXPECT_LE(glm::dot(d, d), 1.f + 1e-6f);
        const vec3 c = square_to_cosine_hemisphere(u);
        EXPECT_GE(c.z, 0.f);
        EXPECT_NEAR(glm::length(c), 1.f, 1e-5f);
        const vec3 s = square_to_uniform_sphere(u);
        EXPECT_NEAR(glm::length(s), 1.f, 1e-5f);
        const vec3 h = square_to_uniform_hemisphere(u);
        EXPECT_GE(h.z, 0.f);
        EXPECT_NEAR(glm::length(h), 1.f, 1e-5f);
        const vec2 b = square_to_triangle(u);
        EXPECT_GE(b.x, 0.f);
        EXPECT_GE(b.y, 0.f);
        EXPECT_LE(b.x + b.y, 1.f + 1e-6f);
        if (HasFailure()) return;
    }
}

// Each pdf integrates to 1 over its domain: midpoint rule over an equal-area (phi, cos theta) grid, where
// d(omega) = d(phi) d(cos theta); the pdfs are smooth, so the quadrature error is far below 1e-4.
TEST(Warp, PdfsIntegrateToOne) {
    const int n = 1000;
    double cos_hemi = 0, uni_sphere = 0, uni_hemi = 0;
    for (int j = 0; j < n; ++j) {
        const double z = -1.0 + 2.0 * (j + 0.5) / n;   // cos theta
        const double cell = (2.0 / n) * (2.0 * M_PI);  // summed over phi (the pdfs do not depend on phi)
        cos_hemi += cosine_hemisphere_pdf(float(z)) * cell;
        uni_sphere += uniform_sphere_pdf() * cell;
        uni_hemi += (z > 0 ? uniform_hemisphere_pdf() : 0.0) * cell;
    }
    EXPECT_NEAR(cos_hemi, 1.0, 1e-4);
    EXPECT_NEAR(uni_sphere, 1.0, 1e-6);
    EXPECT_NEAR(uni_hemi, 1.0, 1e-6);
}

// The concentric map is area-preserving up to pi: a uniform grid of u gives a uniform density on the disk
// (checked by the fraction inside radius r, which must be r^2).
TEST(Warp, ConcentricDiskIsUniform) {
    const int n = 512;
    const float radii[] = {0.25f, 0.5f, 0.75f};
    for (float r : radii) {
        int inside = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const vec2 d = square_to_disk_concentric(vec2((i + 0.5f) / n, (j + 0.5f) / n));
                inside += glm::dot(d, d) < r * r;
            }
        EXPECT_NEAR(double(inside) / (n * n), double(r) * r, 4.0 / n);
    }
}

// ---------------------------------------------------------------- frames

TEST(Frame, OrthonormalAndRightHanded) {
    Pcg32 rng(11, 5);
    std::vector<vec3> normals = {vec3(0, 0, 1),
                                 vec3(0, 0, -1),
                                 vec3(1, 0, 0),
                                 vec3(0, -1, 0),
                                 glm::normalize(vec3(1e-7f, 0, -1)),
                                 glm::normalize(vec3(0, 1e-7f, 1))};
    for (int i = 0; i < 100000; ++i)
        normals.push_back(square_to_uniform_sphere(vec2(rng.next_float(), rng.next_float())));
    for (const vec3& n : normals) {
        const Frame f(n);
        EXPECT_NEAR(glm::length(f.t), 1.f, 1e-5f);
        EXPECT_NEAR(glm::length(f.b), 1.f, 1e-5f);
        EXPECT_NEAR(glm::dot(f.t, f.b), 0.f, 1e-5f);
        EXPECT_NEAR(glm::dot(f.t, f.n), 0.f, 1e-5f);
        EXPECT_NEAR(glm::dot(f.b, f.n), 0.f, 1e-5f);
        EXPECT_NEAR(glm::dot(glm::cross(f.t, f.b), f.n), 1.f, 1e-5f);
        const vec3 w = glm::normalize(vec3(0.3f, -0.5f, 0.8f));
        const vec3 back = f.to_world(f.to_local(w));
        EXPECT_NEAR(glm::length(back - w), 0.f, 1e-5f);
        EXPECT_NEAR(f.to_local(n).z, 1.f, 1e-5f);
        if (HasFailure()) return;
    }
}

// ---------------------------------------------------------------- RNG and sampler

TEST(Rng, NeverReturnsOne) {
    // The largest 24-bit value maps to 1 - 2^-24 exactly.
    EXPECT_EQ(float(0xffffffu) * 0x1p-24f, kOneMinusEpsilon);
    Pcg32 rng(1, 1);
    float hi = 0.f;
    for (int i = 0; i < 4000000; ++i) {
        const float u = rng.next_float();
        ASSERT_LT(u, 1.f);
        ASSERT_GE(u, 0.f);
        hi = std::max(hi, u);
    }
    EXPECT_GT(hi, 0.999f);
}

TEST(Chi2Rng, UniformFrequencies) {
    // Chi-square of 64 equal bins over 1e6 draws; one test at alpha = 0.01.
    Pcg32 rng(42, 54);
    std::vector<double> counts(64, 0.0);
    const int n = 1000000;
    for (int i = 0; i < n; ++i) counts[size_t(rng.next_float() * 64.f)] += 1.0;
    double chi2 = 0.0;
    for (double c : counts) chi2 += (c - n / 64.0) * (c - n / 64.0) / (n / 64.0);
    EXPECT_GT(test::chi2_p_value(chi2, 63.0), 0.01) << "chi2 = " << chi2;
}

TEST(Sampler, SamePixelIndexSeedGivesSameValues) {
    Sampler a(3), b(3), c(4);
    for (uint32_t idx : {0u, 1u, 77u, 1u << 20}) {
        a.start(uvec2(5, 9), idx);
        // Interleave another pixel on b before starting the same one: no hidden state may leak.
        b.start(uvec2(6, 9), idx);
        b.get2d();
        b.start(uvec2(5, 9), idx);
        c.start(uvec2(5, 9), idx);
        bool differs = false;
        for (int d = 0; d < 64; ++d) {
            const float va = a.get1d(), vb = b.get1d(), vc = c.get1d();
            EXPECT_EQ(va, vb);
            EXPECT_LT(va, 1.f);
            differs |= va != vc;
        }
        EXPECT_TRUE(differs) << "seed 3 and seed 4 gave the same stream";
    }
    // Neighbouring pixels and indices give different streams.
    a.start(uvec2(5, 9), 0);
    b.start(uvec2(5, 9), 1);
    c.start(uvec2(6, 9), 0);
    const float va = a.get1d(), vb = b.get1d(), vc = c.get1d();
    EXPECT_TRUE(va != vb || a.get1d() != b.get1d());
    EXPECT_NE(va, vc);
}

// A reserved block's dimensions, drawn in any order or skipped, give the values sequential draws give: skipping a
// draw never shifts the meaning of the dimensions after it (the Sobol sampler's stratification relies on it).
TEST(Sampler, ReservedDimensionsMatchSequentialDraws) {
    Sampler seq(9, SamplerKind::Sobol), lazy(9, SamplerKind::Sobol);
    for (uint32_t idx : {0u, 5u, 1000u}) {
        seq.start(uvec2(2, 3), idx);
        lazy.start(uvec2(2, 3), idx);
        const vec2 a = seq.get2d();
        const float b = seq.get1d();
        const vec2 c = seq.get2d();
        const float d = seq.get1d();
        const uint32_t first = lazy.reserve(4);
        EXPECT_EQ(lazy.get1d_at(first + 3), d);
        EXPECT_EQ(lazy.get2d_at(first + 0), a);  // out of order, dimension first + 1 skipped
        (void)b;
        EXPECT_EQ(lazy.get2d_at(first + 2), c);
        EXPECT_EQ(lazy.get1d(), seq.get1d());  // after the block: the same next dimension
    }
}

// The inline next_float_up/down equal std::nextafter toward +-inf, including at zeros, denormals and infinities.
TEST(Math, NextFloatMatchesNextafter) {
    const float values[] = {0.f,
                            -0.f,
                            1.f,
                            -1.f,
                            1e-40f,
                            -1e-40f,
                            3.4e38f,
                            -3.4e38f,
                            0x1.fffffep127f,
                            -0x1.fffffep127f,
                            1e-3f,
                            123.456f,
                            std::numeric_limits<float>::denorm_min(),
                            HUGE_VALF,
                            -HUGE_VALF};
    for (float v : values) {
        EXPECT_EQ(next_float_up(v), std::nextafter(v, HUGE_VALF)) << v;
        EXPECT_EQ(next_float_down(v), std::nextafter(v, -HUGE_VALF)) << v;
    }
}

// safe_normalize: unit length where |v|^2 overflows (components ~1e20 .. 3e38) or underflows (1e-25) float, the
// same direction as double-precision normalisation, and 0 for zero or non-finite input.
void expect_safe_normalize_handles_huge_and_tiny_vectors() {
    for (float scale : {1e-25f, 1e-3f, 1.f, 1e19f, 1e20f, 3e38f}) {
        const vec3 v = scale * vec3(0.3f, -0.8f, 0.5f);
        const vec3 n = safe_normalize(v);
        const glm::dvec3 ref = glm::normalize(glm::dvec3(0.3, -0.8, 0.5));
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(n[i], ref[i], 1e-6) << "scale " << scale;
    }
    EXPECT_EQ(safe_normalize(vec3(0.f)), vec3(0.f));
    EXPECT_EQ(safe_normalize(vec3(HUGE_VALF, 0.f, 0.f)), vec3(0.f));
    EXPECT_EQ(safe_normalize(vec3(std::nanf(""), 1.f, 0.f)), vec3(0.f));
    EXPECT_EQ(safe_normalize(vec3(0.3f, std::nanf(""), 0.f)), vec3(0.f));
}

TEST(Math, SafeNormalizeHandlesHugeAndTinyVectors) { expect_safe_normalize_handles_huge_and_tiny_vectors(); }

// The same where subnormals are flushed to zero, as in the renderer's threads (Embree's FTZ/DAZ): 1 / 2.4e38 is
// subnormal, so a rescale by a reciprocal gave 0 / 0 = NaN for the 3e38 vector.
TEST(Math, SafeNormalizeHandlesHugeAndTinyVectorsWithFlushToZero) {
    const ScopedFtzDaz ftz;
    expect_safe_normalize_handles_huge_and_tiny_vectors();
}

// ---------------------------------------------------------------- EXR

TEST(Exr, RoundTripIsExactFloatWithMetadata) {
    const test::TestDir dir("pathview_exr");
    Image img(7, 5);
    Pcg32 rng(9, 9);
    for (float& v : img.rgb) v = rng.next_float() * 100.f;
    img.rgb[0] = 1e6f;    // beyond HALF's 65504: must survive as FLOAT
    img.rgb[1] = 1e-30f;  // tiny
    img.rgb[2] = 0.1f;    // not representable in HALF
    const std::string path = (dir.path / "round.exr").string();
    write_exr(path, img, {{"pathview:spp", "17"}, {"pathview:settings", "nee=on mis=on"}});
    Metadata md;
    const Image back = read_exr(path, &md);
    ASSERT_EQ(back.width, 7);
    ASSERT_EQ(back.height, 5);
    for (size_t i = 0; i < img.rgb.size(); ++i) ASSERT_EQ(back.rgb[i], img.rgb[i]) << "at " << i;
    EXPECT_EQ(md["pathview:spp"], "17");
    EXPECT_EQ(md["pathview:settings"], "nee=on mis=on");
    // Nothing but the file itself is left in the folder.
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir.path)) {
        ++files;
        EXPECT_EQ(e.path().filename(), "round.exr");
    }
    EXPECT_EQ(files, 1u);
}

TEST(Exr, UnwritablePathThrowsNamingTheFileAndLeavesNoTemp) {
    const test::TestDir dir("pathview_exr");
    const Image img(4, 4);
    // A folder that does not exist.
    const std::string missing = (dir.path / "nope" / "out.exr").string();
    try {
        write_exr(missing, img);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    }
    // A read-only folder (skipped as root, who can write anywhere).
    const fs::path ro = dir.path / "ro";
    fs::create_directories(ro);
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
    const std::string path = (ro / "out.exr").string();
    if (::access(ro.c_str(), W_OK) != 0) {
        try {
            write_exr(path, img);
            ADD_FAILURE() << "no error";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        }
        EXPECT_TRUE(fs::is_empty(ro)) << "a temporary file was left behind";
    }
    // The target is a folder: the rename fails after the temporary file was written.
    const fs::path as_dir = dir.path / "isdir.exr";
    fs::create_directories(as_dir / "x");
    try {
        write_exr(as_dir.string(), img);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(as_dir.string()), std::string::npos) << e.what();
    }
    fs::permissions(ro, fs::perms::owner_all);
    for (const auto& e : fs::directory_iterator(dir.path))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left " << e.path();
}

TEST(Exr, ReadingAMissingOrBrokenFileThrowsNamingIt) {
    const test::TestDir dir("pathview_exr");
    const std::string missing = (dir.path / "missing.exr").string();
    EXPECT_THROW(read_exr(missing), Error);
    const std::string junk = (dir.path / "junk.exr").string();
    {
        std::FILE* f = std::fopen(junk.c_str(), "wb");
        std::fputs("this is not an EXR file", f);
        std::fclose(f);
    }
    try {
        read_exr(junk);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(junk), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace pv
