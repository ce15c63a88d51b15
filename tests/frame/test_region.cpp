// tests/frame/test_region.cpp: render regions (Renderer::set_region, `pathview render --region`). Inside the region a
// pixel takes exactly the samples of a full render, so it equals the full render's pixel bit for bit; outside no
// sample lands. A whole-image region is the full render. Bad regions give one line and a non-zero exit.
// Test kinds: unit
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <thread>

#include "core/base/error.h"
#include "core/frame/progressive.h"
#include "core/frame/renderer.h"
#include "core/image/image_io.h"
#include "core/load/scene_file.h"
#include "tests/support/cli.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

std::shared_ptr<const Scene> cornell() {
    static const auto scene = std::make_shared<const Scene>(load_scene(builtin_scene_path()));
    return scene;
}

constexpr int kW = 40, kH = 30, kPasses = 4;

// The film after kPasses passes, with `region` (nothing: the whole image).
Film render(std::optional<PixelRect> region, uint64_t* paths = nullptr, SamplerKind sampler = SamplerKind::Sobol) {
    Renderer r(cornell(), 2);
    RenderSettings s;
    s.sampler = sampler;
    r.set_region(region);
    r.restart(cornell()->camera, s, kW, kH);
    for (int i = 0; i < kPasses; ++i) r.render_pass();
    if (paths) *paths = r.stats().paths;
    return r.film();
}

bool same_pixel(const FilmPixel& a, const FilmPixel& b) {
    return std::memcmp(a.sum, b.sum, sizeof a.sum) == 0 && std::memcmp(a.sum_sq, b.sum_sq, sizeof a.sum_sq) == 0 &&
           std::memcmp(a.sum_even, b.sum_even, sizeof a.sum_even) == 0 && a.n == b.n && a.n_even == b.n_even;
}

TEST(Region, PixelsInsideEqualTheFullRenderOutsideUntouched) {
    for (const SamplerKind sampler : {SamplerKind::Sobol, SamplerKind::Independent}) {
        const Film full = render(std::nullopt, nullptr, sampler);
        // Not aligned to the 16-pixel tiles, so that tiles are clipped on every side.
        const PixelRect rect{5, 7, 29, 23};
        uint64_t paths = 0;
        const Film part = render(rect, &paths, sampler);
        EXPECT_EQ(paths, uint64_t(24 * 16 * kPasses));  // every sample inside the region
        int inside = 0, lit = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const FilmPixel& p = part.pixel(x, y);
                if (rect.contains(x, y)) {
                    EXPECT_TRUE(same_pixel(p, full.pixel(x, y))) << x << "," << y;
                    EXPECT_EQ(p.n, uint32_t(kPasses));
                    ++inside;
                    lit += p.sum[0] > 0.0 ? 1 : 0;
                } else {
                    EXPECT_TRUE(same_pixel(p, FilmPixel{})) << x << "," << y;
                }
            }
        EXPECT_EQ(inside, 24 * 16);
        EXPECT_GT(lit, inside / 2);  // the comparison is of real radiance, not of empty pixels
    }
}

TEST(Region, WholeImageRegionIsTheFullRender) {
    const Film full = render(std::nullopt);
    for (const PixelRect rect : {PixelRect{0, 0, kW, kH}, PixelRect{-3, -3, 1000, 1000}}) {  // the second clamped
        const Film same = render(rect);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) ASSERT_TRUE(same_pixel(same.pixel(x, y), full.pixel(x, y))) << x << "," << y;
    }
}

TEST(Region, MetadataAndClamping) {
    Renderer r(cornell(), 2);
    r.restart(cornell()->camera, RenderSettings{}, kW, kH);
    EXPECT_FALSE(r.has_region());
    EXPECT_EQ(render_metadata(r).count("pathview:region"), 0u);
    r.set_region(PixelRect{30, 20, 60, 60});
    r.restart(cornell()->camera, RenderSettings{}, kW, kH);
    EXPECT_TRUE(r.has_region());
    EXPECT_EQ(r.region(), (PixelRect{30, 20, kW, kH}));
    EXPECT_EQ(render_metadata(r).at("pathview:region"), "30,20,40,30");
    // Adaptive sampling would wait forever for the pixels outside: refused.
    AdaptiveSettings a;
    a.noise_threshold = 0.05f;
    r.set_adaptive(a);
    EXPECT_THROW(r.restart(cornell()->camera, RenderSettings{}, kW, kH), Error);
}

TEST(Region, ParseRegion) {
    EXPECT_EQ(parse_region("1,2,3,4", 8, 8, "--region"), (PixelRect{1, 2, 3, 4}));
    EXPECT_EQ(parse_region("0,0,8,8", 8, 8, "--region"), (PixelRect{0, 0, 8, 8}));
    for (const char* bad : {"", "1,2,3", "1,2,3,4,5", "1,2,3,x", "-1,2,3,4", "1, 2,3,4", "1,2,3,4,", "+1,2,3,4",
                            "1.5,2,3,4", "3,2,3,4", "1,4,3,4", "5,2,3,4", "0,0,9,8", "0,0,8,9", "99999999999,0,1,1"}) {
        try {
            parse_region(bad, 8, 8, "--region");
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("--region", 0), 0u) << e.what();
        }
    }
}

// The viewer's driver: a request's region reaches the renderer, the snapshot says it (and its metadata records it),
// no sample lands outside, and a resumable snapshot is refused with a reason.
TEST(RegionProgressive, RequestRegionReachesTheSnapshot) {
    ProgressiveRenderer pr(cornell(), 2);
    RenderRequest req;
    req.camera = cornell()->camera;
    req.width = kW;
    req.height = kH;
    req.region = PixelRect{10, 4, 33, 19};
    const uint64_t g = pr.restart(req);
    ASSERT_TRUE(pr.wait_for(g, 2, std::chrono::seconds(300)));
    Snapshot s;
    ASSERT_TRUE(pr.latest(s));
    EXPECT_EQ(s.region, *req.region);
    EXPECT_EQ(s.metadata.at("pathview:region"), "10,4,33,19");
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const float n = s.samples[size_t(y) * kW + size_t(x)];
            if (req.region->contains(x, y))
                EXPECT_GE(n, 2.f) << x << "," << y;
            else
                EXPECT_EQ(n, 0.f) << x << "," << y;
        }
    pr.request_partial();
    std::string why;
    for (int i = 0; i < 3000 && why.empty(); ++i) {
        why = pr.take_partial_refusal();
        if (why.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    EXPECT_NE(why.find("render region"), std::string::npos) << why;
    EXPECT_FALSE(pr.take_partial());
    // Refused on the caller's thread, nothing posted: a region outside the image, or with adaptive sampling.
    req.region = PixelRect{kW, 0, kW + 5, 5};
    EXPECT_THROW(pr.restart(req), Error);
    req.region = PixelRect{0, 0, 5, 5};
    req.adaptive.noise_threshold = 0.05f;
    EXPECT_THROW(pr.restart(req), Error);
}

// The CLI end to end.
test::RunResult pathview(const std::string& args) { return test::run_command(PATHVIEW_BINARY, args); }

struct CliDir : test::TestDir {
    CliDir() : TestDir("pathview_region") {}
};

const std::string kSize = " --width 24 --height 16 --threads 2 --spp 4 -q";

TEST(RegionCli, RegionMatchesFullRenderInsideAndIsBlackOutside) {
    const CliDir d;
    ASSERT_EQ(pathview("render" + kSize + " -o " + d / "full.exr").exit_code, 0);
    const test::RunResult r = pathview("render --region 3,2,17,11" + kSize + " -o " + d / "region.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("region 3,2,17,11"), std::string::npos) << r.out;
    Metadata meta;
    const Image full = read_exr(d.file("full.exr"));
    const Image region = read_exr(d.file("region.exr"), &meta);
    EXPECT_EQ(meta["pathview:region"], "3,2,17,11");
    ASSERT_EQ(full.rgb.size(), region.rgb.size());
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x) {
            const bool inside = x >= 3 && x < 17 && y >= 2 && y < 11;
            const vec3 want = inside ? full.at(x, y) : vec3(0.f);
            EXPECT_EQ(region.at(x, y).x, want.x) << x << "," << y;
            EXPECT_EQ(region.at(x, y).y, want.y) << x << "," << y;
            EXPECT_EQ(region.at(x, y).z, want.z) << x << "," << y;
        }
}

TEST(RegionCli, BadRegionsExitNonZeroWithOneLine) {
    const CliDir d;
    for (const char* bad : {"1,2,3", "a,b,c,d", "5,5,5,9", "0,0,25,16", "0,0,24,17", "-1,0,4,4", "1,1,2,2,"}) {
        const test::RunResult r = pathview(std::string("render --region '") + bad + "'" + kSize + " -o " + d / "x.exr");
        EXPECT_NE(r.exit_code, 0) << bad;
        EXPECT_EQ(test::line_count(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find("--region"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(d.file("x.exr"))) << bad;
    }
    // Partial renders cover the whole image; adaptive sampling and the denoiser need it too.
    for (const std::string& other :
         {std::string(" --samples 0:4"), std::string(" --shard 0/2"), std::string(" --adaptive on"),
          std::string(" --noise-threshold 0.05"), std::string(" --denoise")}) {
        const std::string size = other == " --samples 0:4" ? " --width 24 --height 16 --threads 2 -q" : kSize;
        const test::RunResult r = pathview("render --region 0,0,4,4" + other + size + " -o " + d / "x.exr");
        EXPECT_NE(r.exit_code, 0) << other;
        EXPECT_EQ(test::line_count(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find("--region with"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(d.file("x.exr"))) << other;
    }
}

}  // namespace
}  // namespace pv
