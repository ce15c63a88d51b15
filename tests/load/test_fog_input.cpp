// tests/load/test_fog_input.cpp: the global medium as the scene file's "fog" and as --fog of render and bench (issue
// 38): parsed values, one-line errors naming the file and the key, and the flag reaching the rendered image.
// Test kinds: unit; regression: BadInputFog
#include <gtest/gtest.h>

#include <filesystem>

#include "core/base/error.h"
#include "core/image/image_io.h"
#include "core/load/scene_file.h"
#include "tests/support/cli.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

std::string cornell_dir() { return fs::path(builtin_scene_path()).parent_path().string(); }

Scene load_with_fog(const std::string& fog) {
    return load_scene_json_text(R"({"obj": "cornell-box.obj", "fog": )" + fog + "}", cornell_dir() + "/fog.json");
}

// The message of the error loading `fog` gives ("" if it loads).
std::string fog_error(const std::string& fog) {
    try {
        load_with_fog(fog);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(SceneFileFog, CoefficientsAlbedoAndDefaults) {
    const Scene none = load_scene_json_text(R"({"obj": "cornell-box.obj"})", cornell_dir() + "/fog.json");
    EXPECT_TRUE(none.fog.empty());

    const Scene a = load_with_fog(R"({"sigma_s": [0.5, 0.25, 0.125], "sigma_a": 0.1, "g": 0.3})");
    EXPECT_EQ(a.fog.sigma_s, vec3(0.5f, 0.25f, 0.125f));
    EXPECT_EQ(a.fog.sigma_a, vec3(0.1f));
    EXPECT_EQ(a.fog.g, 0.3f);

    const Scene b = load_with_fog(R"({"albedo": [1, 0.5, 0], "density": 2})");
    EXPECT_EQ(b.fog.sigma_s, vec3(2.f, 1.f, 0.f));
    EXPECT_EQ(b.fog.sigma_a, vec3(0.f, 1.f, 2.f));
    EXPECT_EQ(b.fog.g, 0.f);

    const Scene c = load_with_fog(R"({"density": 0.5})");  // albedo 1 by default
    EXPECT_EQ(c.fog.sigma_s, vec3(0.5f));
    EXPECT_EQ(c.fog.sigma_a, vec3(0.f));
}

// A material's "medium" (the medium inside a closed mesh of it) takes the fog's keys and errors.
TEST(SceneFileFog, MaterialMedium) {
    const std::string dir = cornell_dir() + "/medium.json";
    const Scene s = load_scene_json_text(
        R"({"obj": "cornell-box.obj", "materials": {"white": {"type": "glass", "ior": 1.33,
            "medium": {"albedo": [0.9, 0.8, 0.7], "density": 2, "g": -0.2}}}})",
        dir);
    bool found = false;
    for (const Material& m : s.materials) {
        if (m.name != "white") {
            EXPECT_TRUE(m.medium.empty()) << m.name;
            continue;
        }
        found = true;
        EXPECT_NEAR(m.medium.sigma_s.x, 1.8f, 1e-6f);
        EXPECT_NEAR(m.medium.sigma_a.z, 0.6f, 1e-6f);
        EXPECT_EQ(m.medium.g, -0.2f);
    }
    EXPECT_TRUE(found);
    try {
        load_scene_json_text(R"({"obj": "cornell-box.obj", "materials": {"white": {"medium": {"sigma_s": -1}}}})", dir);
        ADD_FAILURE() << "a negative coefficient loaded";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("medium.json: /materials/white/medium/sigma_s"), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST(BadInputFog, SceneFileErrorsNameTheFileAndTheKey) {
    const struct {
        const char* fog;
        const char* key;
    } cases[] = {
        {R"({"sigma_s": -1})", "/fog/sigma_s"},
        {R"({"sigma_a": [1, 2]})", "/fog/sigma_a"},
        {R"({"sigma_s": 1, "g": 1})", "/fog/g"},
        {R"({"sigma_s": 1, "density": 1})", "/fog"},
        {R"({"albedo": 0.5})", "/fog/density"},
        {R"({"albedo": 1.5, "density": 1})", "/fog/albedo"},
        {R"(3)", "/fog"},
    };
    for (const auto& c : cases) {
        const std::string e = fog_error(c.fog);
        EXPECT_NE(e.find("fog.json: " + std::string(c.key)), std::string::npos) << c.fog << ": " << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
    const Scene s = load_with_fog(R"({"sigma_s": 1, "sigmas": 2})");
    bool warned = false;
    for (const std::string& w : s.warnings) warned = warned || w.find("/fog/sigmas: unknown key") != std::string::npos;
    EXPECT_TRUE(warned);
}

test::RunResult run_pathview(const std::string& args) { return test::run_command(PATHVIEW_BINARY, args); }

double image_sum(const fs::path& exr) {
    const Image img = read_exr(exr.string());
    double sum = 0.0;
    for (const float v : img.rgb) sum += double(v);
    return sum;
}

// --fog reaches render's and bench's scene: the built-in Cornell box (camera and light a few units apart) in a purely
// absorbing fog of sigma_a = 1000 transmits exp(-1000 x distance): the image is black; without it, it is not.
TEST(BadInputFog, RenderAndBenchApplyTheFlag) {
    const test::TestDir tmp("pathview_fog");
    const fs::path out = tmp.path / "out.exr";
    const std::string render = "render --width 8 --height 8 --spp 2 -q -o '" + out.string() + "'";
    const fs::path ref = tmp.path / "ref.exr";
    const std::string bench =
        "bench --width 6 --height 6 --reference-spp 2 --configs mis/rr/ind --seeds 1 --budget 0.001 --max-spp 1 "
        "--csv '' --svg '' -q --save-reference '" +
        ref.string() + "'";
    for (const bool fog : {false, true}) {
        const std::string flag = fog ? " --fog 0,1000" : "";
        test::RunResult r = run_pathview(render + flag);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        r = run_pathview(bench + flag);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        if (fog) {
            EXPECT_EQ(image_sum(out), 0.0) << "--fog did not reach render";
            EXPECT_EQ(image_sum(ref), 0.0) << "--fog did not reach bench";
        } else {
            EXPECT_GT(image_sum(out), 0.0);
            EXPECT_GT(image_sum(ref), 0.0);
        }
    }
}

// Values out of range are one line naming the flag; malformed ones are CLI11's error naming it (plus its "Run with
// --help" line, as for every flag).
TEST(BadInputFog, BadFlagIsRefused) {
    for (const char* fog : {"-1", "1,-0.5", "1,0,0.995", "1,0,nan", "a", "1,2,3,4"}) {
        const test::RunResult r = run_pathview(
            std::string("render --width 4 --height 4 --spp 1 -q -o /tmp/pathview_cli_unused.exr --fog ") + fog);
        EXPECT_NE(r.exit_code, 0) << fog;
        const std::string first = r.err.substr(0, r.err.find('\n'));
        EXPECT_NE(first.find("--fog"), std::string::npos) << fog << ": " << r.err;
    }
    for (const char* cmd : {"render", "view", "bench"}) {
        const test::RunResult r = run_pathview(std::string(cmd) + " --help");
        EXPECT_NE(r.out.find("--fog"), std::string::npos) << cmd;
    }
}

}  // namespace
}  // namespace pv
