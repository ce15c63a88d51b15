// tests/load/test_bad_input.cpp: golden tests of malformed input (how tinyobjloader reads malformed files, probed under
// ASan/UBSan). Each file in tests/data gives pv::Error naming the file and line, or loads with the documented warning;
// none crashes. Then the CLI: `pathview render` with a missing scene or an unwritable output exits non-zero with one
// line naming the file.
// Test kinds: regression
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/base/error.h"
#include "core/frame/renderer.h"
#include "core/image/image_io.h"
#include "core/load/obj_loader.h"
#include "core/load/scene_file.h"
#include "tests/support/cli.h"
#include "tests/support/scenes.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

std::string data(const std::string& name) { return std::string(PATHVIEW_TEST_DATA) + "/" + name; }

// The message of the pv::Error that loading `name` throws ("" if it loads).
std::string load_error(const std::string& name) {
    try {
        load_scene(data(name));
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

bool has_warning(const Scene& s, const std::string& needle) {
    for (const std::string& w : s.warnings)
        if (w.find(needle) != std::string::npos) return true;
    return false;
}

std::string all_warnings(const Scene& s) {
    std::string out;
    for (const std::string& w : s.warnings) out += "\n  " + w;
    return out;
}

// ---------------------------------------------------------------- errors with file and line

TEST(BadInput, OutOfRangeFaceIndex) {
    EXPECT_EQ(load_error("oob_index.obj"),
              data("oob_index.obj") + ":4: face references vertex 7 but the file defines only 3 vertices");
}

TEST(BadInput, WrappedFaceIndex) {
    // 4294967298 = 2^32 + 2 would silently wrap to 2 in tinyobjloader.
    EXPECT_EQ(
        load_error("wrapped_index.obj"),
        data("wrapped_index.obj") + ":4: face index 4294967298 is out of range; expected an index between 1 and 3");
}

TEST(BadInput, RelativeIndexBeforeFirstVertex) {
    EXPECT_EQ(load_error("bad_relative_index.obj"),
              data("bad_relative_index.obj") +
                  ":4: relative face index -9 reaches before the first vertex; only 3 vertices precede it");
}

TEST(BadInput, ZeroFaceIndex) {
    EXPECT_EQ(load_error("zero_index.obj"),
              data("zero_index.obj") + ":4: face index 0; OBJ indices start at 1 (or are negative, relative)");
}

TEST(BadInput, MissingFile) {
    EXPECT_EQ(load_error("does_not_exist.obj"), data("does_not_exist.obj") + ": no such file; expected an OBJ scene");
}

// ---------------------------------------------------------------- warnings, and what loads

TEST(BadInput, FolderIsNamedAsAFolder) {
    EXPECT_EQ(load_error(""), data("") + ": is a folder; expected a .json scene, an .obj, a .gltf or a .glb");
}

TEST(BadInput, NanVertexDropsItsTriangleWithLine) {
    const Scene s = load_scene(data("v_nan.obj"));
    EXPECT_EQ(s.triangles.size(), 1u);
    EXPECT_EQ(s.stats.dropped_nonfinite, 1u);
    EXPECT_TRUE(
        has_warning(s, data("v_nan.obj") + ":4: vertex 'v nan 1 0' is not finite or beyond 1e18; 1 triangle(s)"))
        << all_warnings(s);
}

TEST(BadInput, HugeVertexDropsItsTriangleWithLine) {
    const Scene s = load_scene(data("v_1e39.obj"));
    EXPECT_EQ(s.triangles.size(), 1u);
    EXPECT_EQ(s.stats.dropped_nonfinite, 1u);
    EXPECT_TRUE(has_warning(s, data("v_1e39.obj") + ":3: vertex 'v 1e39 1 0' is not finite or beyond 1e18"))
        << all_warnings(s);
}

TEST(BadInput, MissingMtlGivesDefaultMaterialAndWarnings) {
    const Scene s = load_scene(data("missing_mtl.obj"));
    ASSERT_EQ(s.triangles.size(), 1u);
    ASSERT_LT(s.material_ids[0], s.materials.size());
    EXPECT_EQ(s.materials[s.material_ids[0]].name, "default");
    EXPECT_TRUE(has_warning(s, "nothere.mtl")) << all_warnings(s);
    EXPECT_TRUE(has_warning(s, "1 triangle(s) have no known material; default grey diffuse (0.8) used"))
        << all_warnings(s);
}

TEST(BadInput, UnknownMaterialGivesDefaultMaterialOnce) {
    const Scene s = load_scene(data("unknown_material.obj"));
    ASSERT_EQ(s.triangles.size(), 2u);
    EXPECT_EQ(s.materials[s.material_ids[0]].name, "default");
    EXPECT_EQ(s.materials[s.material_ids[1]].name, "red");
    EXPECT_TRUE(has_warning(s, "'blue'")) << all_warnings(s);
    EXPECT_EQ(s.stats.default_material_tris, 1u);
}

TEST(BadInput, MissingTextureWarnsAndKeepsKd) {
    const Scene s = load_scene(data("missing_texture.obj"));
    ASSERT_EQ(s.triangles.size(), 1u);
    const Material& m = s.materials[s.material_ids[0]];
    EXPECT_EQ(m.name, "tex");
    ASSERT_TRUE(std::holds_alternative<Lambertian>(m.bsdf));
    EXPECT_EQ(std::get<Lambertian>(m.bsdf).albedo, vec3(0.2f, 0.5f, 0.7f));
    size_t mentions = 0;
    for (const std::string& w : s.warnings) mentions += w.find("missing_texture.png") != std::string::npos;
    EXPECT_EQ(mentions, 1u) << all_warnings(s);
}

TEST(BadInput, EmptyFileIsAnEmptySceneThatRenders) {
    auto s = std::make_shared<Scene>(load_scene(data("empty.obj")));
    EXPECT_EQ(s->triangles.size(), 0u);
    EXPECT_TRUE(has_warning(*s, "no triangles")) << all_warnings(*s);
    // The framing camera of an empty scene is finite, and rendering it gives the background.
    EXPECT_TRUE(is_finite(s->camera.eye) && is_finite(s->camera.target));
    uint64_t dropped = 0;
    const Film f = test::render_with_renderer(s, s->camera, RenderSettings{}, 4, 4, 2, 1, &dropped);
    EXPECT_EQ(dropped, 0u);
    for (float v : f.mean().rgb) EXPECT_TRUE(std::isfinite(v));
}

TEST(BadInput, BinaryJunkNeverCrashes) {
    // 2 KiB of random bytes: parsed as no geometry (or rejected), never a crash or an out-of-bounds read.
    try {
        const Scene s = load_scene(data("binary_junk.obj"));
        EXPECT_EQ(s.triangles.size(), 0u);
        EXPECT_TRUE(has_warning(s, "no triangles")) << all_warnings(s);
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(data("binary_junk.obj")), std::string::npos) << e.what();
    }
}

TEST(BadInput, Utf8BomIsIgnoredWithWarning) {
    const Scene s = load_scene(data("bom.obj"));
    EXPECT_EQ(s.triangles.size(), 1u);  // the first line (a vertex) is not lost
    EXPECT_TRUE(has_warning(s, data("bom.obj") + ": UTF-8 byte-order mark ignored")) << all_warnings(s);
}

TEST(BadInput, CrlfLineEndingsLoadLikeLf) {
    const Scene s = load_scene(data("crlf.obj"));
    ASSERT_EQ(s.triangles.size(), 2u);
    const Material& m = s.materials[s.material_ids[0]];
    EXPECT_EQ(m.name, "red");  // no trailing '\r'
    ASSERT_TRUE(std::holds_alternative<Lambertian>(m.bsdf));
    EXPECT_EQ(std::get<Lambertian>(m.bsdf).albedo, vec3(0.8f, 0.1f, 0.1f));
    EXPECT_EQ(s.stats.default_material_tris, 0u);
}

// An MTL emission of 1e39 parses as +inf: that emitter must not poison the light distribution (it did: every pmf
// became 0 or NaN); its camera hits are dropped samples, and the other lamp is still sampled.
TEST(BadInput, InfiniteEmissionDoesNotPoisonLightSampling) {
    auto s = std::make_shared<Scene>(load_scene(data("ke_inf.obj")));
    ASSERT_EQ(s->triangles.size(), 5u);
    Renderer r(s, 1);
    EXPECT_EQ(r.traceable().triangle_lights().size(), 2u);
    EXPECT_NEAR(r.traceable().triangle_lights().pmf(0) + r.traceable().triangle_lights().pmf(1), 1.f, 1e-6f);
    CameraDesc cam;
    cam.eye = vec3(0.f, 3.f, 6.f);
    cam.target = vec3(0.f);
    r.restart(cam, RenderSettings{}, 16, 16);
    for (int i = 0; i < 4; ++i) r.render_pass();
    double sum = 0.0;
    for (float v : r.film().mean().rgb) {
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
    }
    EXPECT_GT(sum, 0.0);
}

// In-memory variants through load_obj_from_string (the fuzzer's entry point) name the given file.
TEST(BadInput, FromStringNamesTheSource) {
    try {
        load_obj_from_string("v 0 0 0\nv 1 0 0\nf 1 2 3\n", "memory.obj");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "memory.obj:3: face references vertex 3 but the file defines only 2 vertices");
    }
}

// ---------------------------------------------------------------- the CLI

using test::line_count;
using test::RunResult;

RunResult run_pathview(const std::string& args) { return test::run_command(PATHVIEW_BINARY, args); }

TEST(BadInputCli, MissingSceneExitsNonZeroWithOneLine) {
    const std::string missing = data("no_such_scene.obj");
    const RunResult r = run_pathview("render '" + missing + "' --spp 1 -q -o /tmp/pathview_cli_unused.exr");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
}

TEST(BadInputCli, MalformedSceneExitsNonZeroWithFileAndLine) {
    const RunResult r =
        run_pathview("render '" + data("zero_index.obj") + "' --spp 1 -q -o /tmp/pathview_cli_unused.exr");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(data("zero_index.obj") + ":4:"), std::string::npos) << r.err;
}

TEST(BadInputCli, UnwritableOutputExitsNonZeroWithOneLine) {
    // A folder that does not exist, and an output path that is a folder (the final rename fails).
    const std::string nodir = "/nonexistent_pathview_dir/out.exr";
    RunResult r = run_pathview("render --spp 1 --width 8 --height 8 -q -o " + nodir);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(nodir), std::string::npos) << r.err;

    const test::TestDir tmp("pathview_cli");
    const fs::path as_dir = tmp.path / "out.exr";
    fs::create_directories(as_dir / "keep");
    r = run_pathview("render --spp 1 --width 8 --height 8 -q -o '" + as_dir.string() + "'");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(as_dir.string()), std::string::npos) << r.err;
    // No temporary file left next to it.
    for (const auto& e : fs::directory_iterator(as_dir.parent_path()))
        EXPECT_EQ(e.path().filename().string().find(as_dir.filename().string() + ".tmp"), std::string::npos)
            << "left " << e.path();
}

// bench with these --denoise-spp points fails with one line containing `expected`, before anything is rendered.
void expect_bench_denoise_spp_refused(const std::string& points, const std::string& expected) {
    const test::TestDir tmp("pathview_cli");
    const fs::path ref = tmp.path / "ref.exr";
    const RunResult r = run_pathview(
        "bench --width 6 --height 6 --reference-spp 8 --configs mis/rr/ind --seeds 1 --max-spp 16 -q --csv '' "
        "--svg '' --denoise-spp " +
        points + " --save-reference '" + ref.string() + "'");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(test::line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(ref)) << "the reference was rendered before --denoise-spp was checked";
}

// bench --denoise-spp takes points of the series only (powers of two).
TEST(BadInputCli, BenchDenoiseSppMustBeAPointOfTheSeries) {
    expect_bench_denoise_spp_refused("16,12", "--denoise-spp: 12");
}

// A --denoise-spp point past --max-spp was accepted and then never denoised: the bench ran its whole series and
// reported no denoised column. Now one line before anything is rendered.
TEST(BadInputCli, BenchDenoiseSppBeyondMaxSppIsRefused) {
    expect_bench_denoise_spp_refused("32", "--denoise-spp: 32 is beyond --max-spp 16");
}

// An unwritable --csv is found before measuring: nothing is rendered (not even the reference), one line names it.
TEST(BadInputCli, BenchChecksItsOutputsBeforeMeasuring) {
    const test::TestDir tmp("pathview_cli");
    const fs::path ref = tmp.path / "ref.exr";
    const RunResult r = run_pathview(
        "bench --width 6 --height 6 --reference-spp 8 --configs mis/rr/ind --seeds 1 "
        "--budget 0.001 --max-spp 1 -q --csv /nonexistent-pathview-dir/b.csv --svg '' "
        "--save-reference '" +
        ref.string() + "'");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(test::line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("/nonexistent-pathview-dir/b.csv"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(ref)) << "the reference was rendered before the output was checked";
}

// render, view and bench set a scene up through one function (issue 10, item 6): bench applies --environment and
// --sun as render does. A scene without emitters gets the default sky; --environment 0 makes it black everywhere,
// --sun then lights it. Before, bench ignored both (its reference was lit by the default sky).
TEST(BadInputCli, BenchAppliesTheEnvironmentAndSunOverrides) {
    const test::TestDir tmp("pathview_cli");
    const fs::path ref = tmp.path / "ref.exr";
    const std::string bench = "bench '" + data("crlf.obj") +
                              "' --width 6 --height 6 --reference-spp 8 --configs mis/rr/ind "
                              "--seeds 1 --budget 0.001 --max-spp 1 --csv '' --svg '' -q --save-reference '" +
                              ref.string() + "' --environment 0";
    for (const bool sun : {false, true}) {
        const RunResult r = run_pathview(bench + (sun ? " --sun 0.3,1,0.2" : ""));
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const Image img = read_exr(ref.string());
        double sum = 0.0;
        for (const float v : img.rgb) sum += double(v);
        if (sun) {
            EXPECT_GT(sum, 0.0) << "--sun did not light the bench scene";
        } else {
            EXPECT_EQ(sum, 0.0) << "--environment 0 did not reach the bench scene";
        }
        EXPECT_EQ(r.err.find("default sky"), std::string::npos) << r.err;
    }
}

}  // namespace
}  // namespace pv
