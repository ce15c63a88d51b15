// tests/image/test_view_transform_cli.cpp: --view-transform and the OpenColorIO flags of the built program. A PNG
// from `render` or `merge` holds exactly core's display_bytes of the linear image (the function the viewer's PNG
// snapshots go through), the EXR beside it stays linear whatever the transform, and bad flags are one-line errors
// before anything is rendered or written.
// Test kinds: unit
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/image/image_io.h"
#include "core/image/ocio_view.h"
#include "core/image/view_transform.h"
#include "tests/image/ocio_test_config.h"
#include "tests/support/cli.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

test::RunResult pathview(const std::string& args) { return test::run_command(PATHVIEW_BINARY, args); }

std::string bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

const std::string kSize = " --width 24 --height 16 -q";
const std::string kSmall = kSize + " --spp 4";

// The PNG core writes for `exr`'s linear image through `t`.
std::string expected_png(const test::TestDir& d, const std::string& exr, const DisplayTransform& t) {
    const Image img = read_exr(d.file(exr));
    write_png(d.file("expected.png"), img, t);
    return bytes_of(d.file("expected.png"));
}

TEST(ViewTransformCli, RenderPngIsCoreDisplayBytesAndExrStaysLinear) {
    const test::TestDir d("pv_vtcli");
    const test::RunResult clamp = pathview("render" + kSmall + " -o " + d / "c.exr" + " -o " + d / "c.png");
    ASSERT_EQ(clamp.exit_code, 0) << clamp.err;
    for (const char* name : {"reinhard", "aces", "agx", "pbr-neutral"}) {
        const std::string t(name);
        const test::RunResult r = pathview("render" + kSmall + " --exposure 1 --view-transform " + t + " -o " +
                                           d / (t + ".exr") + " -o " + d / (t + ".png"));
        ASSERT_EQ(r.exit_code, 0) << r.err;
        DisplayTransform dt;
        dt.transform = *value_of(kViewTransformNames, t);  // the EXR holds the exposure already
        EXPECT_EQ(bytes_of(d.file(t + ".png")), expected_png(d, t + ".exr", dt)) << t;
        // The EXR is the clamp render's, times 2^1: the transform never reaches it.
        const Image a = read_exr(d.file(t + ".exr")), b = read_exr(d.file("c.exr"));
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_EQ(a.rgb[i], b.rgb[i] * 2.f) << t << " " << i;
    }
    // The default stays clamp (the PNG of earlier versions).
    EXPECT_EQ(bytes_of(d.file("c.png")), expected_png(d, "c.exr", DisplayTransform{}));
}

TEST(ViewTransformCli, OcioConfigViewAndMerge) {
    const test::TestDir d("pv_vtcli");
    const std::string config = d.write("config.ocio", test::kOcioTestConfig);
    const test::RunResult r = pathview("render" + kSmall + " --ocio-config " + d / "config.ocio" +
                                       " --ocio-view 'Gamma 2.2' -o " + d / "o.exr" + " -o " + d / "o.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    DisplayTransform t;
    t.transform = ViewTransform::Ocio;
    t.ocio = std::make_shared<const OcioView>(OcioConfig::load(config), "sRGB", "Gamma 2.2");
    EXPECT_EQ(bytes_of(d.file("o.png")), expected_png(d, "o.exr", t));
    // $OCIO names the config when --ocio-config is not given; merge writes its PNG the same way.
    const test::RunResult part = pathview("render" + kSize + " --samples 0:4 -o " + d / "p.exr");
    ASSERT_EQ(part.exit_code, 0) << part.err;
    const test::RunResult m = test::run_command("env", "OCIO=" + d / "config.ocio" + " " + PATHVIEW_BINARY + " merge " +
                                                           d / "m.exr" + " " + d / "p.exr" + " -o " + d / "m.png" +
                                                           " --view-transform ocio --ocio-view 'Gamma 2.2'");
    ASSERT_EQ(m.exit_code, 0) << m.err;
    EXPECT_EQ(bytes_of(d.file("m.png")), bytes_of(d.file("o.png")));
}

TEST(ViewTransformCli, BadFlagsAreRefusedBeforeRendering) {
    const test::TestDir d("pv_vtcli");
    d.write("config.ocio", test::kOcioTestConfig);
    struct Case {
        std::string flags;
        std::vector<std::string> says;
    };
    const Case cases[] = {
        {"--view-transform filmic", {"--view-transform", "filmic"}},
        {"--view-transform agx --ocio-view Standard", {"--view-transform agx", "ocio only"}},
        {"--ocio-config " + d / "missing.ocio", {d.file("missing.ocio"), "OpenColorIO"}},
        {"--ocio-config " + d / "config.ocio" + " --ocio-display P3", {"no display 'P3'", "'sRGB', 'Raw'"}},
        {"--ocio-config " + d / "config.ocio" + " --ocio-view Filmic", {"no view 'Filmic'"}},
    };
    for (const Case& c : cases) {
        const test::RunResult r = pathview("render" + kSmall + " " + c.flags + " -o " + d / "x.png");
        EXPECT_NE(r.exit_code, 0) << c.flags;
        const std::string first = r.err.substr(0, r.err.find('\n'));  // CLI11 adds a "Run with --help" line
        for (const std::string& s : c.says) EXPECT_TRUE(has(first, s)) << c.flags << ": " << r.err;
        EXPECT_FALSE(fs::exists(d.file("x.png"))) << c.flags;
    }
}

}  // namespace
}  // namespace pv
