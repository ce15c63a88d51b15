// tests/partial/test_untrusted_partial.cpp: partial renders from strangers (issue 26). `pathview merge` and `render
// --resume` read partial EXRs from other machines and old runs: 64-bit sample ranges that never wrap, strict range
// and shard text, finite flags, every output checked before anything is written, refused combinations, short quotes
// of hostile attribute strings, and the merge's memory budget. Each case runs the program: exit code, one line
// naming the file, nothing at the output.
// Test kinds: regression; slow: UntrustedPartialSlow
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cfloat>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/base/error.h"
#include "core/image/image_io.h"
#include "core/partial/partial.h"
#include "core/partial/partial_merge.h"
#include "core/scene/texture.h"
#include "tests/support/cli.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

const std::string kSize = " --width 16 --height 12 --threads 2 -q";

struct Dir : test::TestDir {
    Dir() : TestDir("pathview_partial") {}
};

test::RunResult pathview(const std::string& args) { return test::run_command(PATHVIEW_BINARY, args); }

bool has(const std::string& s, const std::string& needle) { return s.find(needle) != std::string::npos; }

// A refusal: non-zero exit, one line on stderr holding every needle.
void expect_refused(const test::RunResult& r, const std::vector<std::string>& needles) {
    EXPECT_NE(r.exit_code, 0) << r.out;
    EXPECT_EQ(test::line_count(r.err), 1u) << r.err.substr(0, 2000);
    for (const std::string& n : needles) EXPECT_TRUE(has(r.err, n)) << "no '" << n << "' in " << r.err.substr(0, 2000);
}

// Renders part `range` of the box into `name` (a partial EXR).
void render_part(const Dir& d, const std::string& range, const std::string& name) {
    const test::RunResult r = pathview("render --samples " + range + kSize + " -o " + d / name);
    ASSERT_EQ(r.exit_code, 0) << r.err;
}

// Defect 1: ranges are 64-bit: 0:4 and 4:4294967292 merge into 0:4294967296, which reads back and resumes no further.
TEST(UntrustedPartial, SampleRangesNeverWrapAt2To32) {
    const Dir d;
    render_part(d, "0:4", "a.exr");
    render_part(d, "4:1", "b1.exr");
    PartialRender b = read_partial(d.file("b1.exr"));
    b.ranges = {{4, 4294967292ull}};
    write_partial(d.file("b.exr"), b);

    const test::RunResult m =
        pathview("merge --require 0:4294967296 " + d / "m.exr" + " " + d / "a.exr" + " " + d / "b.exr");
    EXPECT_EQ(m.exit_code, 0) << m.err;
    EXPECT_TRUE(has(m.out, "samples 0:4294967296 (4294967296 spp)")) << m.out;
    EXPECT_EQ(format_ranges(read_partial(d.file("m.exr")).ranges), "0:4294967296");
    // --require of all 2^32 indices is not met by 0:5.
    expect_refused(pathview("merge --require 0:4294967296 " + d / "n.png" + " " + d / "a.exr" + " " + d / "b1.exr"),
                   {"--require '0:4294967296'", "hold samples 0:5"});
    EXPECT_FALSE(fs::exists(d.file("n.png")));
    // A part that ends at index 2^32 leaves no room: refused before rendering, naming the file.
    for (const char* more : {" --spp 1", " --time 0.01", ""}) {
        const test::RunResult r = pathview("render --resume " + d / "m.exr" + more + " -q -o " + d / "r.exr");
        expect_refused(r, {d.file("m.exr"), "ends at sample 4294967296"});
        EXPECT_FALSE(fs::exists(d.file("r.exr")));
    }
    // 2^32 samples in one process: refused, not 0 spp.
    expect_refused(pathview("render --samples 0:4294967296" + kSize + " -o " + d / "x.png"),
                   {"--samples '0:4294967296'", "COUNT <= 2^30"});
    EXPECT_FALSE(fs::exists(d.file("x.png")));
    // Shards report the numbers given, never wrapped ones.
    expect_refused(pathview("render --spp 8 --shard 0/4294967296" + kSize + " -o " + d / "x.exr"),
                   {"0/4294967296", "8 samples cannot fill 4294967296 shards"});
    expect_refused(pathview("render --spp 8 --shard -1/4" + kSize + " -o " + d / "x.exr"),
                   {"--shard '-1/4'", "expected INDEX/COUNT"});
    EXPECT_FALSE(fs::exists(d.file("x.exr")));
}

// Defect 11: strict text for --samples, --require and --shard.
TEST(UntrustedPartial, RangeAndShardTextIsStrict) {
    const Dir d;
    for (const char* bad : {"4:+4", "' 4:4'", "04:4", "4:4,", "4:4,,5:1", "+4:4"}) {
        const test::RunResult r = pathview("render --samples " + std::string(bad) + kSize + " -o " + d / "x.exr");
        expect_refused(r, {"--samples", "expected START:COUNT"});
    }
    for (const char* bad : {"+1/4", "01/4", "1/4,", "' 1/4'"})
        expect_refused(pathview("render --spp 8 --shard " + std::string(bad) + kSize + " -o " + d / "x.exr"),
                       {"--shard", "expected INDEX/COUNT"});
    EXPECT_TRUE(d.holds_only({}));
}

// Defect 4: merge's --exposure is finite and within render's range; a large one saturates in the PNG.
TEST(UntrustedPartial, MergeExposureIsFinite) {
    const Dir d;
    render_part(d, "0:2", "a.exr");
    for (const char* bad : {"nan", "inf", "-inf", "1e9", "65"}) {
        const test::RunResult r =
            pathview("merge --exposure " + std::string(bad) + " " + d / "m.png" + " " + d / "a.exr");
        EXPECT_NE(r.exit_code, 0) << bad;
        EXPECT_TRUE(has(r.err.substr(0, r.err.find('\n')), "not a finite number in [-64, 64]")) << bad << r.err;
        EXPECT_FALSE(fs::exists(d.file("m.png"))) << bad;
    }
    const test::RunResult ok = pathview("merge --exposure 64 " + d / "m.png" + " " + d / "a.exr");
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    float brightest = 0.f;
    for (const vec4& t : Texture::load(d.file("m.png")).texels()) brightest = std::max(brightest, t.x);
    EXPECT_EQ(brightest, 1.f);  // the lit pixels saturate to white, not NaN-to-black
}

// Defect 5: every output is checked before the first is written.
TEST(UntrustedPartial, MergeChecksEveryOutputFirst) {
    const Dir d;
    render_part(d, "0:2", "a.exr");
    const test::RunResult r =
        pathview("merge " + d / "m.exr" + " " + d / "a.exr" + " -o " + d / "missing/dir/out.png -o " + d / "m.png");
    expect_refused(r, {d.file("missing/dir/out.png"), "does not exist"});
    EXPECT_TRUE(d.holds_only({"a.exr"}));
}

// Defect 7: --aovs and --denoise with a partial render are refused (a part holds only the film's sums).
TEST(UntrustedPartial, LayersWithPartialRendersAreRefused) {
    const Dir d;
    render_part(d, "0:2", "a.exr");
    for (const char* flag : {"--aovs", "--denoise"}) {
        expect_refused(pathview("render --samples 0:2 " + std::string(flag) + kSize + " -o " + d / "x.exr"),
                       {flag, "with --samples", "a partial render holds only"});
        expect_refused(pathview("render --spp 4 --shard 0/2 " + std::string(flag) + kSize + " -o " + d / "x.exr"),
                       {flag, "with --shard"});
        expect_refused(pathview("render --resume " + d / "a.exr" + " --spp 1 -q " + flag + " -o " + d / "x.exr"),
                       {flag, "with --resume"});
    }
    EXPECT_TRUE(d.holds_only({"a.exr"}));
}

// Defect 8: a 1 MB attribute string is quoted by a short prefix in the one error line.
TEST(UntrustedPartial, HugeAttributeStringsGiveAShortErrorLine) {
    const Dir d;
    render_part(d, "0:2", "a.exr");
    PartialRender p = read_partial(d.file("a.exr"));
    p.id.settings = std::string(1 << 20, 'x');
    write_partial(d.file("s.exr"), p);
    p = read_partial(d.file("a.exr"));
    p.info["pathview:scene_flags"] = std::string(1 << 20, '-');
    write_partial(d.file("f.exr"), p);
    const test::RunResult m = pathview("merge " + d / "m.exr" + " " + d / "s.exr");
    expect_refused(m, {d.file("s.exr"), "(1048576 bytes)"});
    EXPECT_LT(m.err.size(), 400u);
    const test::RunResult r = pathview("render --resume " + d / "f.exr" + " --spp 1 -q -o " + d / "r.exr");
    expect_refused(r, {d.file("f.exr"), "pathview:scene_flags", "(1048576 bytes)"});
    EXPECT_LT(r.err.size(), 600u);
    p = read_partial(d.file("a.exr"));
    p.info["pathview:scene"] = std::string(1 << 20, 'p');
    write_partial(d.file("p.exr"), p);
    const test::RunResult q = pathview("render --resume " + d / "p.exr" + " --spp 1 -q -o " + d / "r.exr");
    expect_refused(q, {d.file("p.exr"), "pathview:scene", "(1048576 bytes)"});
    EXPECT_LT(q.err.size(), 600u);
    EXPECT_FALSE(fs::exists(d.file("r.exr")));
}

// Defect 11: a bookmark without a name is listed with a warning saying what was expected; an empty name is an error.
TEST(UntrustedPartial, NamelessBookmarksAreNotSilent) {
    const Dir d;
    const std::string obj = std::string(PATHVIEW_FUZZ_DIR) + "/../../assets/cornell-box/cornell-box.obj";
    std::ofstream(d.file("s.json")) << R"({"obj": ")" << obj << R"(", "bookmarks": [{"eye": [278, 273, -800]}]})";
    const test::RunResult r =
        pathview("render " + d / "s.json" + " --bookmark 'view 1' --spp 1" + kSize + " -o " + d / "x.png");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(has(r.err, "/bookmarks/0: no \"name\"; expected the bookmark's name")) << r.err;
    std::ofstream(d.file("e.json")) << R"({"obj": ")" << obj << R"(", "bookmarks": [{"name": ""}]})";
    expect_refused(pathview("render " + d / "e.json" + " --spp 1" + kSize + " -o " + d / "y.png"),
                   {d.file("e.json"), "/bookmarks/0/name: empty"});
    EXPECT_FALSE(fs::exists(d.file("y.png")));
}

// A part of the box with its film replaced by `px` (w x h).
void write_with_pixels(const Dir& d, const std::string& from, const std::string& name, int w, int h,
                       std::vector<FilmPixel> px) {
    PartialRender p = read_partial(d.file(from));
    p.id.width = w;
    p.id.height = h;
    p.film = Film::from_pixels(w, h, std::move(px));
    write_partial(d.file(name), p);
}

// Defect 2: sums beyond what float samples can give (DBL_MAX: finite, but Inf once divided into a float mean or
// added) are refused naming the file, and nothing is written; a merge whose sum overflows names the part.
TEST(UntrustedPartial, OverflowingSumsAreRefused) {
    const Dir d;
    render_part(d, "0:2", "a.exr");
    render_part(d, "2:2", "b.exr");
    std::vector<FilmPixel> px = read_partial(d.file("a.exr")).film.pixels();
    for (FilmPixel& f : px)
        for (int c = 0; c < 3; ++c) f.sum[c] = f.sum_sq[c] = f.sum_even[c] = DBL_MAX;
    write_with_pixels(d, "a.exr", "huge.exr", 16, 12, px);
    for (const std::string& parts : {d / "huge.exr", d / "huge.exr" + " " + d / "b.exr"}) {
        const test::RunResult r = pathview("merge " + d / "m.exr" + " " + parts + " -o " + d / "m.png");
        expect_refused(r, {d.file("huge.exr"), "larger than its 2 samples of finite float radiance can give"});
    }
    EXPECT_FALSE(fs::exists(d.file("m.exr")) || fs::exists(d.file("m.png")));
    // In memory (not read from a file, so not checked on reading): the sum that overflows names its part.
    PartialRender a = read_partial(d.file("a.exr")), b = read_partial(d.file("b.exr"));
    std::vector<FilmPixel> big = a.film.pixels();
    big[5].sum[1] = DBL_MAX;
    big[5].n = 1;
    a.film = Film::from_pixels(16, 12, big);
    b.film = Film::from_pixels(16, 12, big);
    try {
        merge_partials({a, b}, {"a.exr", "b.exr"});
        ADD_FAILURE() << "merged into Inf";
    } catch (const Error& e) {
        EXPECT_TRUE(has(e.what(), "b.exr: pixel (5, 0): adding this part's sum overflows")) << e.what();
    }
}

// Defect 3: merge takes the image budget of every reader (--max-image-megapixels) and refuses a part too small for
// the size it declares before reading any pixel.
TEST(UntrustedPartial, MergeHasTheImageBudgetAndSizeChecks) {
    const Dir d;
    render_part(d, "0:2", "a.exr");
    write_with_pixels(d, "a.exr", "z.exr", 1024, 1024, std::vector<FilmPixel>(1024 * 1024));
    expect_refused(pathview("merge --max-image-megapixels 0.5 " + d / "m.exr" + " " + d / "z.exr"),
                   {d.file("z.exr"), "1024x1024", "--max-image-megapixels"});
    std::ifstream in(d.file("z.exr"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bytes.resize(bytes.size() / 2);
    std::ofstream(d.file("cut.exr"), std::ios::binary) << bytes;
    expect_refused(pathview("merge " + d / "m.exr" + " " + d / "cut.exr"),
                   {d.file("cut.exr"), "declares 1024x1024 pixels but has only"});
    EXPECT_FALSE(fs::exists(d.file("m.exr")));
}

// Peak resident memory (kB) of the program run with `args` (no shell), from wait4.
long peak_rss_kb(const std::vector<std::string>& args, int& exit_code) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        std::vector<char*> argv{const_cast<char*>(PATHVIEW_BINARY)};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(PATHVIEW_BINARY, argv.data());
        ::_exit(127);
    }
    int status = 0;
    struct rusage ru {};
    ::wait4(pid, &status, 0, &ru);
    exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return ru.ru_maxrss;
}

// Defect 3: a merge holds the output film (80 bytes a pixel) and one block of rows of a part, not whole parts.
// (Slow: skipped under ASan, whose quarantine keeps freed blocks.)
TEST(UntrustedPartialSlow, MergeMemoryIsTheOutputPlusABlock) {
    const Dir d;
    render_part(d, "0:2", "a.exr");
    constexpr int kSide = 1024;
    write_with_pixels(d, "a.exr", "z.exr", kSide, kSide, std::vector<FilmPixel>(kSide * kSide));
    int code = -1;
    const long idle = peak_rss_kb({"merge", "--help"}, code);
    const long rss = peak_rss_kb({"merge", d.file("m.exr"), d.file("z.exr")}, code);
    EXPECT_EQ(code, 0);
    // The output film, plus 32 MB for a block, OpenEXR and the program; reading the part whole took 270 MB.
    const double film_kb = double(sizeof(FilmPixel)) * kSide * kSide / 1024.0;
    EXPECT_LT(double(rss - idle), film_kb + 32 * 1024) << rss << " kB peak, " << idle << " kB idle";
}

// Defect 6: radiance whose squares overflow the float Variance layer and the denoisers (NFOR gave an all-black image,
// Variance Inf) is refused with --denoise or --aovs, naming the figure; nothing is written. Within the bound the
// denoised image is finite and not black.
TEST(UntrustedPartial, DenoisingRadianceBeyondFloatSquaresIsRefused) {
    const Dir d;
    for (const char* flags : {"--denoise", "--aovs", "--denoise --denoiser atrous"}) {
        const test::RunResult r =
            pathview("render --environment 1e30 --spp 4 " + std::string(flags) + kSize + " -o " + d / "x.exr");
        expect_refused(r, {"RMS radiance is", "beyond the 1e+16"});
        EXPECT_FALSE(fs::exists(d.file("x.exr")));
    }
    const test::RunResult ok =
        pathview("render --environment 1e15 --spp 4 --denoise --aovs" + kSize + " -o " + d / "ok.exr");
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    const Image im = read_exr(d.file("ok.exr"));
    size_t zero = 0;
    for (float v : im.rgb) {
        EXPECT_TRUE(std::isfinite(v));
        zero += v == 0.f;
    }
    EXPECT_EQ(zero, 0u);  // the box's open front lets the constant sky light every pixel
    // Without the features, the same render is written as is.
    EXPECT_EQ(pathview("render --environment 1e30 --spp 1" + kSize + " -o " + d / "plain.exr").exit_code, 0);
}

// The fuzzer's seeds (tests/fuzz/corpus-partial) are valid parts of this version that merge and round-trip; its
// reproducers end in an error naming the file. (A version change makes the seeds foreign: regenerate them with
// tests/fuzz/make_partial_corpus.sh.)
TEST(UntrustedPartial, FuzzCorpusSeedsMergeAndReproducersAreRefused) {
    size_t seeds = 0, repros = 0;
    for (const auto& entry : fs::directory_iterator(std::string(PATHVIEW_FUZZ_DIR) + "/corpus-partial")) {
        const std::string path = entry.path().string(), name = entry.path().filename().string();
        if (name.rfind("seed_", 0) == 0) {
            ++seeds;
            const PartialRender p = merge_partial_files({path});
            EXPECT_TRUE(std::isfinite(p.film.estimated_rel_mse())) << name;
            EXPECT_EQ(format_ranges(p.ranges), format_ranges(read_partial(path).ranges)) << name;
        } else if (name == "repro_dblmax_sums.exr") {
            ++repros;
            try {
                merge_partial_files({path});
                ADD_FAILURE() << name << " was merged";
            } catch (const Error& e) {
                EXPECT_TRUE(has(e.what(), path + ": pixel (0, 0) has a sum")) << e.what();
            }
        }
    }
    EXPECT_GE(seeds, 3u);
    EXPECT_EQ(repros, 1u);
}

// Defect 3: parts whose merged film does not fit the memory available are refused up front with the figure, as
// `render` refuses a film (the old merge ended in std::bad_alloc). ulimit -v: not under ASan (Slow).
TEST(UntrustedPartialSlow, MergeRefusesAFilmLargerThanMemory) {
    const Dir d;
    render_part(d, "0:2", "a.exr");
    write_with_pixels(d, "a.exr", "z.exr", 2048, 2048, std::vector<FilmPixel>(2048 * 2048));
    const std::string cmd = "ulimit -v 300000; '" + std::string(PATHVIEW_BINARY) + "' merge " + d / "m.exr" + " " +
                            d / "z.exr" + " 2>" + d / "err.txt";
    const int status = std::system(("/bin/sh -c \"" + cmd + "\"").c_str());
    EXPECT_NE(status, 0);
    std::ifstream in(d.file("err.txt"));
    std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_TRUE(has(err, d.file("z.exr") + ": 2048x2048 parts need about 0.4 GB to merge")) << err;
    EXPECT_FALSE(fs::exists(d.file("m.exr")));
}

// ---------------------------------------------------------------- deploy/slurm (defect 9)

std::string deploy_dir() { return fs::canonical(std::string(PATHVIEW_FUZZ_DIR) + "/../../deploy/slurm").string(); }

// The NUL-separated arguments recorded by the fake commands below, one call after another.
std::vector<std::string> recorded(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<std::string> args;
    for (std::string a; std::getline(in, a, '\0');) args.push_back(a);
    return args;
}

// A folder with a fake `sbatch` on PATH: it records its arguments (each NUL-terminated, then "<end>") in
// sbatch.log and prints a job id.
struct FakeSlurm {
    Dir d;
    FakeSlurm() {
        fs::create_directories(d.path / "bin");
        std::ofstream(d.file("bin/sbatch")) << "#!/bin/bash\nprintf '%s\\0' \"$@\" '<end>' >> \""
                                            << d.file("sbatch.log") << "\"\necho '4242;cluster'\n";
        fs::permissions(d.path / "bin/sbatch", fs::perms::owner_all);
    }
    test::RunResult submit(const std::string& args) const {
        return run_in(d.path, "PATH=\"" + d.file("bin") + ":$PATH\" exec \"" + deploy_dir() + "/submit.sh\" \"$@\"",
                      args);
    }
    // Runs `line` by a script in `dir` (cd there first) with the shell arguments `args`.
    static test::RunResult run_in(const fs::path& dir, const std::string& line, const std::string& args) {
        const std::string script = (dir / "run.sh").string();
        std::ofstream(script) << "#!/bin/bash\ncd \"" << dir.string() << "\" || exit 99\n" << line << "\n";
        fs::permissions(script, fs::perms::owner_all);
        return test::run_command(script, args);
    }
};

// The count is validated as a positive integer before any arithmetic; nothing is submitted otherwise.
TEST(UntrustedSlurm, SubmitCountMustBeAPositiveInteger) {
    const FakeSlurm s;
    for (const char* bad : {"'x[$(touch PWNED)]'", "0", "-1", "+3", "03", "''", "1e3", "' 4'", "'4 '", "9999999999"}) {
        const test::RunResult r = s.submit(bad);
        EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
        EXPECT_TRUE(has(r.err, "is not a positive integer")) << bad << ": " << r.err;
    }
    EXPECT_FALSE(fs::exists(s.d.file("PWNED"))) << "the count was evaluated as shell arithmetic";
    EXPECT_FALSE(fs::exists(s.d.file("sbatch.log"))) << "a bad count was submitted";
}

// Render flags after -- reach the array job's script whole (spaces, globs); sbatch options go to both jobs.
TEST(UntrustedSlurm, SubmitKeepsRenderFlagsWhole) {
    const FakeSlurm s;
    std::ofstream(s.d.file("decoy.exr")) << "x";  // a `*` expanded in the submitting folder would name it
    const test::RunResult r = s.submit("3 --partition=p -- --environment '/a b/c  d.exr' '*' --seed 5");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out, "4242 4242\n");
    const std::string script = deploy_dir() + "/render-array.sbatch";
    const std::vector<std::string> expected = {"--parsable",
                                               "--array=0-2",
                                               "--partition=p",
                                               script,
                                               "--environment",
                                               "/a b/c  d.exr",
                                               "*",
                                               "--seed",
                                               "5",
                                               "<end>",
                                               "--parsable",
                                               "--dependency=afterok:4242",
                                               "--kill-on-invalid-dep=yes",
                                               "--partition=p",
                                               deploy_dir() + "/merge.sbatch",
                                               "<end>"};
    const std::vector<std::string> got = recorded(s.d.file("sbatch.log"));
    ASSERT_EQ(got.size(), expected.size());
    EXPECT_EQ(got, expected);

    // The array task passes them on whole; PV_FLAGS (the older form) is split at whitespace but never globbed.
    std::ofstream(s.d.file("bin/fake-pathview"))
        << "#!/bin/bash\nprintf '%s\\0' \"$@\" > \"" << s.d.file("args.log") << "\"\n";
    fs::permissions(s.d.path / "bin/fake-pathview", fs::perms::owner_all);
    const test::RunResult task = FakeSlurm::run_in(
        s.d.path,
        "PATHVIEW=\"" + s.d.file("bin/fake-pathview") + "\" PV_SPP=8 PV_PARTS=\"" + s.d.file("parts") +
            "\" PV_FLAGS='--width 8 *' SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_COUNT=3 exec \"" +
            script + "\" \"$@\"",
        "--environment '/a b/c  d.exr' '*'");
    ASSERT_EQ(task.exit_code, 0) << task.err;
    const std::vector<std::string> args = recorded(s.d.file("args.log"));
    const std::vector<std::string> want = {"render",        "--spp",     "8",  "--shard",
                                           "1/3",           "--threads", "1",  "-q",
                                           "--width",       "8",         "*",  "--environment",
                                           "/a b/c  d.exr", "*",         "-o", s.d.file("parts") + "/part-0001.exr"};
    EXPECT_EQ(args, want);
}

}  // namespace
}  // namespace pv
