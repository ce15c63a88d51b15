// tests/frame/test_light_groups_cli.cpp: `pathview render --light-groups / --light-gain` end to end: gains of 1 write
// the image of a render without them, bit for bit; a gain changes it; bad gains, unknown groups and partial renders
// are refused with one line and no file.
// Test kinds: unit
#include <gtest/gtest.h>

#include <filesystem>

#include "core/image/image_io.h"
#include "support/cli.h"
#include "support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

test::RunResult pathview(const std::string& args) { return test::run_command(PATHVIEW_BINARY, args); }

struct CliDir : test::TestDir {
    CliDir() : TestDir("pathview_light_groups") {}
};

const std::string kScene = std::string(" '") + PATHVIEW_ASSETS + "/mis-plates/scene.json'";
const std::string kSize = " --width 24 --height 16 --threads 2 --spp 4 -q";

TEST(LightGroupsCli, UnitGainsKeepTheImageAndAGainChangesIt) {
    const CliDir d;
    ASSERT_EQ(pathview("render" + kScene + kSize + " -o " + d / "plain.exr").exit_code, 0);
    const test::RunResult r =
        pathview("render" + kScene + kSize + " --light-groups --light-gain light0=1 -o " + d / "ones.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_EQ(pathview("render" + kScene + kSize + " --light-gain light1=0 -o " + d / "muted.exr").exit_code, 0);
    Metadata meta;
    const Image plain = read_exr(d.file("plain.exr"));
    const Image ones = read_exr(d.file("ones.exr"), &meta);
    const Image muted = read_exr(d.file("muted.exr"));
    EXPECT_EQ(plain.rgb, ones.rgb);
    EXPECT_NE(plain.rgb, muted.rgb);
    EXPECT_EQ(meta["pathview:light_groups"], "light0;light1;light2;light3");
}

TEST(LightGroupsCli, BadGainsExitNonZeroWithOneLine) {
    const CliDir d;
    for (const char* bad : {"nope=2", "light0", "=2", "light0=-1", "light0=1,2", "light0=a", "light0=nan"}) {
        const test::RunResult r = pathview("render" + kScene + kSize + " --light-gain '" + bad + "' -o " + d / "x.exr");
        EXPECT_NE(r.exit_code, 0) << bad;
        EXPECT_EQ(test::line_count(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find("--light-gain"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(d.file("x.exr"))) << bad;
    }
    const test::RunResult r =
        pathview("render" + kScene + " --width 24 --height 16 -q --samples 0:4 --light-groups -o " + d / "x.exr");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(test::line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("partial"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace pv
