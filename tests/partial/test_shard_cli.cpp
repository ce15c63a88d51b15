// tests/partial/test_shard_cli.cpp: the partial-render commands end to end: `pathview render --samples START:COUNT`,
// `pathview merge` and `pathview render --resume` against one `pathview render --spp N`; bad parts give one line
// naming the file, a non-zero exit, and nothing (not even a temporary) at the output path.
// Test kinds: unit
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/image/image_io.h"
#include "core/partial/partial.h"
#include "core/render/settings.h"
#include "tests/support/cli.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

const std::string kSize = " --width 24 --height 16 --threads 2 -q";

struct CliDir : test::TestDir {
    CliDir() : TestDir("pathview_shardcli") {}
};

test::RunResult pathview(const std::string& args) { return test::run_command(PATHVIEW_BINARY, args); }

void expect_ok(const test::RunResult& r) { EXPECT_EQ(r.exit_code, 0) << r.err; }

// Adaptive sampling's allocation comes from a pilot over the whole render, so it cannot be split into parts that
// merge bit for bit: --adaptive on with a partial render is refused with one line naming the flag.
TEST(ShardCli, AdaptiveOnWithAPartialRenderIsRefused) {
    const CliDir d;
    for (const std::string& part : {std::string(" --samples 0:16"), std::string(" --spp 16 --shard 0/2")}) {
        const test::RunResult r = pathview("render --adaptive on" + part + kSize + " -o " + d / "p.exr");
        EXPECT_NE(r.exit_code, 0) << part;
        EXPECT_NE(r.err.find("--adaptive on cannot be split"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(d.file("p.exr")));
    }
    expect_ok(pathview("render --adaptive off --samples 0:4" + kSize + " -o " + d / "p.exr"));
    const test::RunResult r =
        pathview("render --adaptive on --resume " + d / "p.exr" + " --spp 4 -q -o " + d / "q.exr");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("--resume"), std::string::npos) << r.err;
}

TEST(ShardCli, MergedShardsAndResumedPartEqualOneRender) {
    const CliDir d;
    // Every pixel at every index, as the parts (adaptive sampling would start only at 16 spp anyway).
    expect_ok(pathview("render --spp 8 --adaptive off" + kSize + " -o " + d / "single.exr"));
    expect_ok(pathview("render --samples 0:4" + kSize + " -o " + d / "a.exr"));
    // --shard 1/2 of --spp 8 is --samples 4:4.
    expect_ok(pathview("render --spp 8 --shard 1/2" + kSize + " -o " + d / "b.exr" + " -o " + d / "b.png"));
    const test::RunResult m = pathview("merge --require 0:8 " + d / "merged.exr" + " " + d / "b.exr" + " " +
                                       d / "a.exr" + " -o " + d / "merged.png");
    expect_ok(m);
    EXPECT_NE(m.out.find("samples 0:8 (8 spp)"), std::string::npos) << m.out;
    EXPECT_TRUE(fs::exists(d.file("merged.png")));
    EXPECT_TRUE(fs::exists(d.file("b.png")));

    const Image single = read_exr(d.file("single.exr"));
    const Image merged = read_exr(d.file("merged.exr"));
    ASSERT_EQ(single.rgb.size(), merged.rgb.size());
    for (size_t i = 0; i < single.rgb.size(); ++i)
        EXPECT_LE(std::fabs(single.rgb[i] - merged.rgb[i]), 1e-6f * single.rgb[i]) << i;

    // Resuming the first shard with 4 more samples adds indices 4..7 onto its exact sums: bit for bit.
    expect_ok(pathview("render --resume " + d / "a.exr" + " --spp 4 --threads 1 -q -o " + d / "resumed.exr"));
    const PartialRender resumed = read_partial(d.file("resumed.exr"));
    EXPECT_EQ(format_ranges(resumed.ranges), "0:8");
    EXPECT_EQ(read_exr(d.file("resumed.exr")).rgb, single.rgb);
    // A merged file resumes too, and image-defining flags are refused with --resume.
    expect_ok(pathview("render --resume " + d / "merged.exr" + " --spp 1 -q -o " + d / "more.exr"));
    EXPECT_EQ(format_ranges(read_partial(d.file("more.exr")).ranges), "0:9");
    // With --time, as many whole samples as fit, from START, at most COUNT.
    expect_ok(pathview("render --samples 100:100000 --time 0.05" + kSize + " -o " + d / "timed.exr"));
    const PartialRender timed = read_partial(d.file("timed.exr"));
    ASSERT_EQ(timed.ranges.size(), 1u);
    EXPECT_EQ(timed.ranges[0].start, 100u);
    EXPECT_GE(timed.ranges[0].count, 1u);
    EXPECT_LT(timed.ranges[0].count, 100000u);
    const test::RunResult flagged = pathview("render --resume " + d / "a.exr" + " --seed 3 -q -o " + d / "x.exr");
    EXPECT_NE(flagged.exit_code, 0);
    EXPECT_NE(flagged.err.find("--seed comes from the part"), std::string::npos) << flagged.err;
}

// Every field of the settings table (core/render/settings.h) comes from the part: --resume refuses its flag with
// one line, and accepts the part alone.
TEST(ShardCli, ResumeRefusesEverySettingFlag) {
    const CliDir d;
    expect_ok(pathview("render --samples 0:1" + kSize + " -o " + d / "a.exr"));
    for_each_setting([&](const auto& f) {
        const std::string value = f.name_count ? f.names[0].name : "1";
        const test::RunResult r =
            pathview("render --resume " + d / "a.exr" + " " + f.flag + " " + value + " -q -o " + d / "x.exr");
        EXPECT_NE(r.exit_code, 0) << f.flag;
        EXPECT_NE(r.err.find(std::string(f.flag) + " comes from the part"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(d.file("x.exr"))) << f.flag;
    });
    expect_ok(pathview("render --resume " + d / "a.exr" + " --spp 1 -q -o " + d / "x.exr"));
}

TEST(ShardCli, BadPartsLeaveNothingAtTheOutput) {
    const CliDir d;
    expect_ok(pathview("render --samples 0:2" + kSize + " -o " + d / "a.exr"));
    expect_ok(pathview("render --samples 1:2" + kSize + " -o " + d / "overlap.exr"));
    expect_ok(pathview("render --samples 2:2 --seed 5" + kSize + " -o " + d / "seed.exr"));
    expect_ok(pathview("render --samples 2:2 --width 25 --height 16 --threads 2 -q -o " + d / "size.exr"));
    expect_ok(pathview("render --samples 2:2 --environment 0.5" + kSize + " -o " + d / "scene.exr"));
    expect_ok(pathview("render --spp 2" + kSize + " -o " + d / "plain.exr"));
    {
        std::ifstream in(d.file("a.exr"), std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream(d.file("cut.exr"), std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() * 3 / 4));
    }
    const struct {
        const char* part;
        const char* says;
    } cases[] = {{"overlap.exr", "overlaps 0:2"}, {"seed.exr", "settings"},       {"size.exr", "size"},
                 {"scene.exr", "scene"},          {"plain.exr", "not a partial"}, {"cut.exr", "cut.exr"}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.part);
        const test::RunResult r =
            pathview("merge " + d / "out.exr" + " " + d / "a.exr" + " " + d / c.part + " -o " + d / "out.png");
        EXPECT_NE(r.exit_code, 0);
        EXPECT_EQ(test::line_count(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find(d.file(c.part)), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
        for (const auto& e : fs::directory_iterator(d.path))
            EXPECT_EQ(e.path().filename().string().rfind("out.", 0), std::string::npos) << "wrote " << e.path();
    }
    // A missing shard: --require names the ranges there are.
    const test::RunResult gap = pathview("merge --require 0:8 " + d / "out.exr" + " " + d / "a.exr");
    EXPECT_NE(gap.exit_code, 0);
    EXPECT_NE(gap.err.find("the parts hold samples 0:2"), std::string::npos) << gap.err;
    EXPECT_FALSE(fs::exists(d.file("out.exr")));

    // Resuming from a part of another scene: the scene named on the command line differs.
    const std::string other = fs::path(PATHVIEW_ASSETS).append("mis-plates/scene.json").string();
    const test::RunResult r =
        pathview("render '" + other + "' --resume " + d / "a.exr" + " --spp 1 -q -o " + d / "out.exr");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(test::line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("scene hash differs"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d.file("out.exr")));
}

}  // namespace
}  // namespace pv
