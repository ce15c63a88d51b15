// tests/load/test_untrusted.cpp: files people download (issue #15). Each crafted input of tests/fuzz/corpus-* ends in a
// clear error naming the file (or loads with a warning), in bounded time and memory. Inputs that made the old code
// loop forever run in a child process with a time limit, so a regression fails instead of hanging the suite; the
// child's peak RSS (wait4) is the memory figure. Image writers: full disk (RLIMIT_FSIZE), folders, long names,
// stale temporary files.
// Test kinds: regression
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <thread>

#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/image/image_io.h"
#include "core/load/scene_file.h"
#include "core/scene/texture.h"
#include "tests/support/child.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

std::string image(const std::string& name) { return std::string(PATHVIEW_FUZZ_DIR) + "/corpus-image/" + name; }
std::string json_input(const std::string& name) { return std::string(PATHVIEW_FUZZ_DIR) + "/corpus-json/" + name; }

struct TempDir {
    fs::path path;
    TempDir() {
        char tmpl[] = "/tmp/pathview_untrusted_XXXXXX";
        path = ::mkdtemp(tmpl);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string file(const std::string& name, const std::string& text) const {
        const std::string p = (path / name).string();
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
};

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

using test::ChildResult;
using test::kDeadlineSeconds;
using test::run_bounded;

bool contains(const std::string& s, const std::string& needle) { return s.find(needle) != std::string::npos; }

// The pv::Error message of loading `path` as a texture ("" if it loads).
std::string texture_error(const std::string& path, std::vector<std::string>* warnings = nullptr) {
    try {
        Texture::load(path, false, warnings);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// Child exit codes: 0 = the expected error naming the file, 1 = loaded, 2 = another message.
int expect_error_child(const std::string& path, const std::string& needle) {
    const std::string e = texture_error(path);
    if (e.empty()) return 1;
    std::fprintf(stderr, "%s\n", e.c_str());
    return contains(e, path) && contains(e, needle) ? 0 : 2;
}

// ---------------------------------------------------------------- hangs

TEST(UntrustedImage, HdrRunLengthCountZeroEndsInAnError) {
    const std::string f = image("repro_hdr_rle_count0.hdr");
    const ChildResult r = run_bounded([&] { return expect_error_child(f, "count of 0"); });
    ASSERT_TRUE(r.finished) << "loading " << f << " did not end within the deadline";
    EXPECT_EQ(r.exit_code, 0);
}

TEST(UntrustedImage, HdrEndingInsideARunEndsInAnError) {
    for (const char* name : {"repro_hdr_rle_ends_in_run.hdr", "repro_truncated_rle.hdr"}) {
        const std::string f = image(name);
        const ChildResult r = run_bounded([&] { return expect_error_child(f, "truncated"); });
        ASSERT_TRUE(r.finished) << "loading " << f << " did not end within the deadline";
        EXPECT_EQ(r.exit_code, 0) << f;
    }
}

TEST(UntrustedImage, HangingHdrAsMapKdTextureGivesAWarning) {
    TempDir dir;
    fs::copy_file(image("repro_hdr_rle_count0.hdr"), dir.path / "hang.hdr");
    dir.file("m.mtl", "newmtl m\nKd 0.5 0.5 0.5\nmap_Kd hang.hdr\n");
    const std::string obj = dir.file("t.obj",
                                     "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                     "usemtl m\nf 1/1 2/2 3/3\n");
    const ChildResult r = run_bounded([&] {
        const Scene s = load_scene(obj);
        for (const std::string& w : s.warnings)
            if (contains(w, (dir.path / "hang.hdr").string()) && contains(w, "count of 0")) return 0;
        return 2;
    });
    ASSERT_TRUE(r.finished) << "loading the scene did not end within the deadline";
    EXPECT_EQ(r.exit_code, 0);
}

TEST(UntrustedImage, FifoSceneFileAndMtllibAreRefused) {
    TempDir dir;
    const std::string fifo_json = (dir.path / "scene.json").string(), fifo_obj = (dir.path / "scene.obj").string();
    const std::string fifo_mtl = (dir.path / "fifo.mtl").string();
    ASSERT_EQ(::mkfifo(fifo_json.c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo(fifo_obj.c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo(fifo_mtl.c_str(), 0600), 0);
    fs::create_symlink("/dev/zero", dir.path / "zero.mtl");
    const std::string with_fifo = dir.file("a.obj", "mtllib fifo.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string with_zero = dir.file("b.obj", "mtllib zero.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fs::create_directories(dir.path / "folder.json");
    const ChildResult r = run_bounded([&] {
        int bad = 0;
        for (const std::string& p : {fifo_json, fifo_obj, (dir.path / "folder.json").string()}) {
            try {
                load_scene(p);
                bad |= 1;
            } catch (const Error& e) {
                std::fprintf(stderr, "%s\n", e.what());
                if (!contains(e.what(), p) || !(contains(e.what(), "FIFO") || contains(e.what(), "folder"))) bad |= 2;
            }
        }
        for (const auto& [obj, needle] : {std::pair{with_fifo, "is a FIFO"}, std::pair{with_zero, "is a device"}}) {
            const Scene s = load_scene(obj);
            bool found = false;
            for (const std::string& w : s.warnings) found = found || contains(w, needle);
            if (!found) bad |= 4;
        }
        return bad;
    });
    ASSERT_TRUE(r.finished) << "a FIFO or /dev/zero was read: no end within the deadline";
    EXPECT_EQ(r.exit_code, 0);
    const ChildResult idle = run_bounded([] { return 0; });
    EXPECT_LT(r.max_rss_kb - idle.max_rss_kb, 64 * 1024);
}

// ---------------------------------------------------------------- memory

TEST(UntrustedImage, TinyFilesDeclaringHugeImagesAreRefusedWithinLittleMemory) {
    // The child's peak RSS with nothing loaded (the forked test binary; larger under sanitizers).
    const ChildResult idle = run_bounded([] { return 0; });
    ASSERT_TRUE(idle.finished);
    for (const char* name :
         {"repro_huge.tga", "repro_huge.bmp", "repro_huge.ppm", "repro_huge.gif", "repro_huge.psd", "repro_huge.jpg",
          "repro_huge_11585.hdr", "repro_huge_window.exr", "repro_exr_attr_2gb.exr"}) {
        const std::string f = image(name);
        const ChildResult r = run_bounded([&] { return expect_error_child(f, "declares"); });
        ASSERT_TRUE(r.finished) << f;
        EXPECT_EQ(r.exit_code, 0) << f;
        // Decoding any of these would take gigabytes; refusing them takes next to nothing.
        EXPECT_LT(r.max_rss_kb - idle.max_rss_kb, 64 * 1024) << f;
    }
}

TEST(UntrustedImage, TheBudgetIsAFlagAndTheMessageSaysSo) {
    const ImageLimits saved = image_limits();
    set_image_limits(ImageLimits{100});  // seed.png is 16x8 = 128 pixels
    const std::string e = texture_error(image("seed.png"));
    set_image_limits(saved);
    EXPECT_TRUE(contains(e, image("seed.png")) && contains(e, "16x8") && contains(e, "--max-image-megapixels")) << e;
    EXPECT_EQ(texture_error(image("seed.png")), "");
}

// ---------------------------------------------------------------- valid and damaged images

TEST(UntrustedImage, EveryValidSeedLoadsWithoutWarning) {
    for (const auto& entry : fs::directory_iterator(std::string(PATHVIEW_FUZZ_DIR) + "/corpus-image")) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("seed", 0) != 0) continue;
        std::vector<std::string> warnings;
        Texture t;
        ASSERT_NO_THROW(t = Texture::load(entry.path().string(), false, &warnings)) << name;
        EXPECT_GT(t.width(), 0) << name;
        EXPECT_TRUE(warnings.empty()) << name << ": " << (warnings.empty() ? "" : warnings[0]);
    }
    // The EXR seed is 0.5 everywhere; the HDR seed's first texel is RGBE (100, 80, 60, 128) of row 0... as stb
    // decodes it: (m + 0.5) / 256 * 2^(e - 128).
    const Texture exr = Texture::load(image("seed.exr"));
    EXPECT_EQ(exr.lookup(vec2(0.3f, 0.7f)), vec4(0.5f, 0.5f, 0.5f, 1.f));
}

// Every regression input of the fuzzers' corpus loads or gives an error naming the file; under the sanitizers
// (make test-asan) any undefined behaviour on the way fails the run. regression_exr_negative_origin.exr: a data
// window with a negative origin made the old slice-pointer arithmetic overflow; regression_exr_offset_wraps.exr:
// a chunk offset near 2^64 wrapped the in-memory stream's bounds check (both found by fuzz_image).
TEST(UntrustedImage, EveryFuzzRegressionInputEndsCleanly) {
    size_t n = 0;
    for (const auto& entry : fs::directory_iterator(std::string(PATHVIEW_FUZZ_DIR) + "/corpus-image")) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("regression_", 0) != 0) continue;
        ++n;
        const ChildResult r = run_bounded([&] {
            const std::string e = texture_error(entry.path().string());
            if (!e.empty() && !contains(e, entry.path().string())) return 2;
            try {  // the fuzzer's path: from memory
                Texture::decode(slurp(entry.path().string()), name);
            } catch (const Error& err) {
                return contains(err.what(), name) ? 0 : 3;
            }
            return 0;
        });
        ASSERT_TRUE(r.finished) << name;
        EXPECT_EQ(r.exit_code, 0) << name;
    }
    EXPECT_GE(n, 1u);
}

TEST(UntrustedImage, TexelsAreSanitisedSoLookupsStayFinite) {
    const float big = std::numeric_limits<float>::max(), nan = std::numeric_limits<float>::quiet_NaN();
    const Texture t(2, 2, {vec4(big), vec4(big, big, big, 1.f), vec4(nan, 0.f, 0.f, 1.f), vec4(-5.f, big, 0.f, 1.f)});
    for (int i = 0; i < 1000; ++i) {
        const vec2 uv(float(i) * 0.00137f, float(i) * 0.00291f);
        const vec4 v = t.lookup(uv);
        ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w)) << i;
        ASSERT_TRUE(v.x >= 0.f && v.x <= Texture::kMaxTexel) << i;
    }
}

TEST(UntrustedImage, TruncatedImagesWarnNamingTheFile) {
    for (const char* name : {"repro_truncated.tga", "repro_truncated.bmp", "repro_truncated.ppm", "repro_truncated.hdr",
                             "repro_truncated.gif", "repro_truncated.psd", "repro_truncated.jpg"}) {
        std::vector<std::string> warnings;
        const std::string f = image(name);
        const std::string e = texture_error(f, &warnings);
        if (!e.empty()) {  // refusing is allowed too, if the message names the file
            EXPECT_TRUE(contains(e, f)) << e;
            continue;
        }
        ASSERT_EQ(warnings.size(), 1u) << f;
        EXPECT_TRUE(contains(warnings[0], f) && contains(warnings[0], "ends early")) << warnings[0];
    }
}

TEST(UntrustedImage, StbFailuresGiveAReadableReason) {
    TempDir dir;
    for (const std::string& bytes :
         {std::string("this is not an image at all, just text"), std::string("BM\x01\x02", 4),
          std::string("\x89PNG\r\n\x1a\n\0\0\0\0IHDR", 16), std::string()}) {
        const std::string f = dir.file("junk.png", bytes);
        const std::string e = texture_error(f);
        EXPECT_TRUE(contains(e, f + ": cannot read image: ")) << e;
        const std::string reason = e.substr(e.find("cannot read image: ") + 19);
        EXPECT_GT(reason.size(), 10u) << e;
        for (unsigned char c : reason) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << e;
    }
}

// ---------------------------------------------------------------- outputs

Image noise_image(int w, int h) {
    Image img(w, h);
    uint32_t x = 12345;
    for (float& v : img.rgb) {
        x = x * 1664525u + 1013904223u;
        v = float(x >> 8) / float(1 << 24);
    }
    return img;
}

TEST(UntrustedOutput, FullDiskFailsAndLeavesNoFile) {
    // RLIMIT_FSIZE makes write() fail with EFBIG past 4 KB, as a full disk fails with ENOSPC.
    TempDir dir;
    const Image img = noise_image(64, 64);
    for (const char* name : {"out.png", "out.exr"}) {
        const std::string path = (dir.path / name).string();
        const ChildResult r = run_bounded([&] {
            ::signal(SIGXFSZ, SIG_IGN);
            struct rlimit lim {
                4096, 4096
            };
            ::setrlimit(RLIMIT_FSIZE, &lim);
            try {
                write_image(path, img);
            } catch (const Error& e) {
                std::fprintf(stderr, "%s\n", e.what());
                return contains(e.what(), path) ? 0 : 2;
            }
            return 1;
        });
        ASSERT_TRUE(r.finished);
        EXPECT_EQ(r.exit_code, 0) << name << ": no error on a full disk";
        EXPECT_FALSE(fs::exists(path)) << name << ": a truncated file was left at the final name";
    }
    EXPECT_TRUE(fs::is_empty(dir.path)) << "a temporary file was left behind";
}

TEST(UntrustedOutput, FolderAsOutputSaysSoNotSuccess) {
    TempDir dir;
    fs::create_directories(dir.path / "out.png");
    try {
        write_png((dir.path / "out.png").string(), noise_image(4, 4));
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_TRUE(contains(e.what(), "folder")) << e.what();
        EXPECT_FALSE(contains(e.what(), "Success")) << e.what();
    }
    EXPECT_THROW(check_writable((dir.path / "out.png").string()), Error);
    EXPECT_THROW(check_writable((dir.path / "missing" / "a.exr").string()), Error);
    EXPECT_NO_THROW(check_writable((dir.path / "fine.exr").string()));
    EXPECT_FALSE(fs::exists(dir.path / "fine.exr"));
}

TEST(UntrustedOutput, LongestValidNameIsWritten) {
    TempDir dir;
    const std::string name = std::string(250, 'n') + ".png";  // 254 characters: NAME_MAX is 255
    const std::string path = (dir.path / name).string();
    ASSERT_NO_THROW(write_png(path, noise_image(4, 4)));
    EXPECT_TRUE(fs::is_regular_file(path));
    EXPECT_EQ(slurp(path).substr(1, 3), "PNG");
}

TEST(UntrustedOutput, StaleTemporaryFilesOfDeadWritersAreRemoved) {
    TempDir dir;
    // A pid that certainly is dead: a child that has exited and been reaped.
    const pid_t dead = ::fork();
    if (dead == 0) ::_exit(0);
    ::waitpid(dead, nullptr, 0);
    const auto old = fs::file_time_type::clock::now() - std::chrono::minutes(10);
    const fs::path stale = dir.path / atomic_temp_name(dead, 3);
    const fs::path fresh = dir.path / atomic_temp_name(dead, 4);         // dead writer, but written just now
    const fs::path alive = dir.path / atomic_temp_name(::getppid(), 5);  // a live process's
    const fs::path other = dir.path / ".pv-notapid-1.tmp";
    for (const fs::path& p : {stale, fresh, alive, other}) std::ofstream(p) << "partial";
    fs::last_write_time(stale, old);
    fs::last_write_time(alive, old);
    fs::last_write_time(other, old);
    write_png((dir.path / "out.png").string(), noise_image(4, 4));
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(fresh));
    EXPECT_TRUE(fs::exists(alive));
    EXPECT_TRUE(fs::exists(other));
}

TEST(UntrustedOutput, SigkillDuringAWriteLeavesOnlyATemporaryTheNextWriteRemoves) {
    TempDir dir;
    const std::string out = (dir.path / "out.exr").string();
    const Image img = noise_image(512, 512);
    // A writer that writes forever; it is killed while a temporary file of its own exists.
    const pid_t child = ::fork();
    if (child == 0) {
        for (;;) write_exr(out, img);
    }
    const std::string prefix = ".pv-" + std::to_string(child) + "-";
    fs::path temp;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kDeadlineSeconds);
    while (temp.empty() && std::chrono::steady_clock::now() < deadline) {
        std::error_code ec;
        for (fs::directory_iterator it(dir.path, ec), end; !ec && it != end; it.increment(ec))
            if (it->path().filename().string().rfind(prefix, 0) == 0) {
                ::kill(child, SIGKILL);
                temp = it->path();
                break;
            }
    }
    ::kill(child, SIGKILL);
    ::waitpid(child, nullptr, 0);
    ASSERT_FALSE(temp.empty()) << "never saw the writer's temporary file";
    // What is left: the temporary (the final name holds the last whole file, if any, and is a valid EXR).
    std::error_code ec;
    if (fs::exists(out)) {
        EXPECT_EQ(read_exr(out).width, 512);
    }
    ASSERT_TRUE(fs::exists(temp, ec));
    fs::last_write_time(temp, fs::file_time_type::clock::now() - std::chrono::minutes(2));
    write_png((dir.path / "next.png").string(), noise_image(4, 4));
    EXPECT_FALSE(fs::exists(temp)) << "the dead writer's temporary file was not removed";
}

// ---------------------------------------------------------------- JSON scene files

TEST(UntrustedJson, ErrorsNameTheFileAndTheKey) {
    TempDir dir;
    dir.file("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    dir.file("lit.obj", "mtllib lit.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
    dir.file("lit.mtl", "newmtl m\nKd 0.5 0.5 0.5\nKe 1 1 1\n");
    const std::pair<const char*, const char*> cases[] = {
        {"repro_two_sided_string.json", "/two_sided_emitters: expected true or false"},
        {"repro_fov_string.json", "/camera/fov: expected a number in [0.01, 179]"},
        {"repro_aperture_negative.json", "/camera/aperture: expected a number in [0, 1e+30]"},
        {"repro_strength_negative.json", "/environment/strength: expected a number in [0, 1e+30]"},
        {"repro_radius_negative.json", "/sun/angular_radius: expected a number in [0.01, 45]"},
        {"repro_environment_number.json", "/environment: expected an object"},
        {"repro_sun_string.json", "/sun: expected an object"},
        {"repro_material_number.json", "/materials/m: expected an object"},
        {"repro_bookmarks_object.json", "/bookmarks: expected an array"},
    };
    for (const auto& [name, expected] : cases) {
        const std::string path = (dir.path / name).string();
        fs::copy_file(json_input(name), path);
        try {
            load_scene(path);
            ADD_FAILURE() << name << ": loaded";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), path + ": " + expected);
        }
    }
    // The seeds load; an unknown key is a warning naming its path.
    fs::copy_file(json_input("seed_full.json"), dir.path / "full.json");
    EXPECT_NO_THROW(load_scene((dir.path / "full.json").string()));
    const std::string typo = dir.file("typo.json", R"({"obj": "a.obj", "camera": {"fvo": 30}})");
    const Scene s = load_scene(typo);
    bool warned = false;
    for (const std::string& w : s.warnings) warned = warned || w == typo + ": /camera/fvo: unknown key, ignored";
    EXPECT_TRUE(warned);
}

// ---------------------------------------------------------------- the CLI

struct RunResult {
    int exit_code = -1;
    std::string out, err;
};

// Runs the program with a time limit (timeout(1) kills it: exit 137).
RunResult run_pathview(const std::string& args, int seconds = kDeadlineSeconds, const std::string& prefix = "") {
    TempDir dir;
    const std::string out = (dir.path / "stdout").string(), err = (dir.path / "stderr").string();
    const std::string cmd = prefix + "timeout -s KILL " + std::to_string(seconds) + " '" + PATHVIEW_BINARY + "' " +
                            args + " >'" + out + "' 2>'" + err + "'";
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

size_t lines(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

TEST(UntrustedCli, NonFiniteFlagsAreRejected) {
    TempDir dir;
    const std::string out = (dir.path / "o.exr").string();
    for (const char* flag : {"--time nan", "--time inf", "--exposure 1000", "--exposure nan", "--exposure inf",
                             "--sun-radius nan", "--env-strength nan", "--aperture nan", "--focus-distance nan",
                             "--sun-irradiance nan", "--fov nan", "--env-rotation inf", "--eye 0,nan,1"}) {
        const RunResult r = run_pathview("render --width 8 --height 8 -q " + std::string(flag) + " -o " + out);
        EXPECT_NE(r.exit_code, 0) << flag;
        EXPECT_NE(r.exit_code, 137) << flag << ": still running at the deadline";
        // CLI11's usage errors add "Run with --help": the first line names the flag.
        EXPECT_TRUE(contains(r.err.substr(0, r.err.find('\n')), "not a finite number")) << flag << ": " << r.err;
        EXPECT_FALSE(fs::exists(out)) << flag;
    }
}

TEST(UntrustedCli, HangingEnvironmentMapEndsInOneLine) {
    const std::string f = image("repro_hdr_rle_count0.hdr");
    const RunResult r =
        run_pathview("render --width 8 --height 8 --spp 1 -q --environment '" + f + "' -o /tmp/unused.exr");
    EXPECT_NE(r.exit_code, 137) << "still running at the deadline";
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_TRUE(contains(r.err, f)) << r.err;
}

TEST(UntrustedCli, MissingOutputFolderIsFoundBeforeRendering) {
    // A render of hours: only a check before it can end in seconds.
    const std::string out = "/nonexistent_pathview_dir/out.exr";
    const RunResult r = run_pathview("render --spp 1000000 -q -o " + out);
    EXPECT_NE(r.exit_code, 137) << "rendered before checking the output";
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_TRUE(contains(r.err, out) && contains(r.err, "does not exist")) << r.err;
}

TEST(UntrustedCli, ThreadsReportsWhatRan) {
    TempDir dir;
    cpu_set_t cpus;
    ASSERT_EQ(sched_getaffinity(0, sizeof cpus, &cpus), 0);
    const int usable = CPU_COUNT(&cpus);
    const RunResult r =
        run_pathview("render --width 8 --height 8 --spp 1 -q --threads 1024 -o " + (dir.path / "o.exr").string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, ", " + std::to_string(usable) + " threads,")) << r.out;
    EXPECT_TRUE(contains(r.err, "--threads 1024")) << r.err;
}

#if !defined( \
    PATHVIEW_SANITIZED)  // (clang defines no __SANITIZE_ADDRESS__; CMake defines this for every sanitizer build)
TEST(UntrustedCli, FilmLargerThanMemoryIsRefusedUpFrontWithTheFigure) {
    // 4 GB of address space: 16384^2 pixels at 92 bytes need 24.7 GB. (Sanitizers reserve terabytes: not there.)
    const RunResult r = run_pathview("render --width 16384 --height 16384 --spp 1 -q -o /tmp/unused.exr",
                                     kDeadlineSeconds, "ulimit -v 4000000; ");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_TRUE(contains(r.err, "24.7 GB")) << r.err;
    EXPECT_FALSE(contains(r.err, "internal error")) << r.err;
}
#endif

}  // namespace
}  // namespace pv
