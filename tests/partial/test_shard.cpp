// tests/partial/test_shard.cpp: partial renders (core/partial/partial.h). Four shards of a 64-spp render merged through
// their files equal the single render (the stored double sums are exact; only the order of the double additions
// differs, so the sums agree within the recursive-summation bound and the float means bit for bit or within
// one float ulp); a resumed part equals the single render bit for bit; the file round-trips exactly; bad parts
// (overlapping, mismatched, truncated, another scene or version, not a partial) give one-line errors naming the file.
// Test kinds: unit; regression: ShardBadInput
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include "core/base/error.h"
#include "core/frame/renderer.h"
#include "core/frame/renderer_partial.h"
#include "core/image/image_io.h"
#include "core/partial/partial.h"
#include "core/partial/partial_merge.h"
#include "tests/support/scenes.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 32, kH = 24;

// A fresh folder per test, removed afterwards.
struct TempDir : test::TestDir {
    TempDir() : TestDir("pathview_shard") {}
};

RenderSettings settings_with(SamplerKind kind, uint32_t seed = 0) {
    RenderSettings s;
    s.sampler = kind;
    s.seed = seed;
    return s;
}

// Renders sample indices [start, start + count) of the Cornell box into a partial render.
PartialRender render_part(Renderer& r, const RenderSettings& s, uint32_t start, uint32_t count, int w = kW,
                          int h = kH) {
    r.restart(test::cornell_box()->camera, s, w, h);
    r.set_next_sample(start);
    for (uint32_t i = 0; i < count; ++i) r.render_pass();
    return partial_from_renderer(r, {{start, count}});
}

Renderer& cornell_renderer() {
    static Renderer r(test::cornell_box(), 2);
    return r;
}

// Distance in float ulps (both finite, same sign).
int64_t ulps(float a, float b) {
    int32_t ia, ib;
    std::memcpy(&ia, &a, 4);
    std::memcpy(&ib, &b, 4);
    return std::llabs(int64_t(ia) - int64_t(ib));
}

bool same_pixels(const Film& a, const Film& b) {
    if (a.width() != b.width() || a.height() != b.height()) return false;
    return std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(FilmPixel)) == 0;
}

TEST(ShardMerge, FourShardsOfSixtyFourEqualOneRender) {
    const TempDir dir;
    Renderer& r = cornell_renderer();
    for (SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Independent}) {
        SCOPED_TRACE(sampler_name(kind));
        const RenderSettings s = settings_with(kind);
        const Film single = render_part(r, s, 0, 64).film;
        // Shards written to files and read back, given to the merge out of order.
        std::vector<PartialRender> parts;
        std::vector<std::string> names;
        for (uint32_t start : {48u, 16u, 0u, 32u}) {
            names.push_back(dir.file("part" + std::to_string(start) + ".exr"));
            write_partial(names.back(), render_part(r, s, start, 16));
            parts.push_back(read_partial(names.back()));
        }
        const PartialRender merged = merge_partials(parts, names);
        ASSERT_EQ(format_ranges(merged.ranges), "0:64");

        // Recursive summation of n non-negative terms errs by at most (n - 1) u sum (Higham, Accuracy and Stability
        // of Numerical Algorithms, 2002, eq. 4.4), so two summation orders differ by at most 2 (n - 1) u sum.
        const double u = std::ldexp(1.0, -53);
        const Image a = single.mean(), b = merged.film.mean();
        size_t identical = 0;
        int64_t worst_ulps = 0;
        for (size_t i = 0; i < single.pixels().size(); ++i) {
            const FilmPixel& p = single.pixels()[i];
            const FilmPixel& q = merged.film.pixels()[i];
            ASSERT_EQ(p.n, q.n);
            ASSERT_EQ(p.n_even, q.n_even);
            for (int c = 0; c < 3; ++c) {
                EXPECT_LE(std::fabs(p.sum[c] - q.sum[c]), 2.0 * (p.n - 1) * u * p.sum[c]) << i;
                EXPECT_LE(std::fabs(p.sum_sq[c] - q.sum_sq[c]), 2.0 * (p.n - 1) * u * p.sum_sq[c]) << i;
                EXPECT_LE(std::fabs(p.sum_even[c] - q.sum_even[c]), 2.0 * (p.n_even - 1) * u * p.sum_even[c]) << i;
            }
        }
        for (size_t i = 0; i < a.rgb.size(); ++i) {
            identical += a.rgb[i] == b.rgb[i];
            worst_ulps = std::max(worst_ulps, ulps(a.rgb[i], b.rgb[i]));
            EXPECT_LE(std::fabs(a.rgb[i] - b.rgb[i]), 1e-6f * std::fabs(a.rgb[i])) << i;
        }
        // The double sums differ by ~1e-16 relative: a float mean changes only if it lies that close to a rounding
        // boundary, so at most one ulp, and in practice never.
        EXPECT_LE(worst_ulps, 1);
        std::printf("[ %s ] %zu of %zu mean values bit-identical to the single render\n", sampler_name(kind), identical,
                    a.rgb.size());

        // The merged file carries the image as R, G, B and the half-buffer estimate of the merged sums.
        write_partial(dir.file("merged.exr"), merged);
        Metadata meta;
        const Image from_file = read_exr(dir.file("merged.exr"), &meta);
        EXPECT_EQ(from_file.rgb, b.rgb);
        EXPECT_EQ(meta["pathview:spp"], "64");
        EXPECT_EQ(meta["pathview:samples"], "0:64");
        const double est = single.estimated_rel_mse();
        ASSERT_GT(est, 0.0);
        // Written with 6 significant digits.
        EXPECT_NEAR(std::stod(meta["pathview:rel_mse_estimate"]), est, 1e-5 * est);
    }
}

TEST(ShardResume, ContinuedPartEqualsOneRenderBitForBit) {
    const TempDir dir;
    Renderer& r = cornell_renderer();
    const RenderSettings s = settings_with(SamplerKind::Sobol, 7);
    const Film single = render_part(r, s, 0, 64).film;

    write_partial(dir.file("first.exr"), render_part(r, s, 0, 40));
    const PartialRender part = read_partial(dir.file("first.exr"));
    // What `pathview render --resume` does: the part's sums, then indices from the part's end.
    r.restart(parse_camera(part.id.camera, "part"), parse_settings(part.id.settings, "part"), part.id.width,
              part.id.height);
    EXPECT_EQ(scene_hash(r.scene(), r.traceable().materials(), r.traceable().environment_settings()),
              part.id.scene_hash);
    r.load_film(part.film);
    r.set_next_sample(uint32_t(part.ranges.back().end()));
    for (int i = 0; i < 24; ++i) r.render_pass();
    // Each pixel adds the same samples in the same order as the single render.
    EXPECT_TRUE(same_pixels(r.film(), single));
}

TEST(ShardFormat, RoundTripIsExact) {
    const TempDir dir;
    Renderer& r = cornell_renderer();
    const PartialRender part = render_part(r, settings_with(SamplerKind::Sobol, 3), 5, 3);
    write_partial(dir.file("p.exr"), part);
    const PartialRender back = read_partial(dir.file("p.exr"));
    EXPECT_TRUE(same_pixels(part.film, back.film));
    EXPECT_EQ(back.id.version, part.id.version);
    EXPECT_EQ(back.id.scene_hash, part.id.scene_hash);
    EXPECT_EQ(back.id.settings, part.id.settings);
    EXPECT_EQ(back.id.camera, part.id.camera);
    EXPECT_EQ(back.id.width, kW);
    EXPECT_EQ(back.id.height, kH);
    EXPECT_EQ(format_ranges(back.ranges), "5:3");
    // Settings and camera text parse back to what was rendered.
    EXPECT_EQ(parse_settings(back.id.settings, "p"), r.settings_as_rendered());  // sky_guide off: not applicable
    EXPECT_EQ(camera_text(parse_camera(back.id.camera, "p")), camera_text(r.camera().desc()));
}

TEST(ShardFormat, SceneHashSeesMaterialsEnvironmentAndGeometry) {
    const Scene& scene = *test::cornell_box();
    const EnvironmentSettings env = scene.environment;
    const uint64_t h = scene_hash(scene, scene.materials, env);
    EXPECT_EQ(h, scene_hash(scene, scene.materials, env));
    std::vector<Material> edited = scene.materials;
    set_base_color(edited[0].bsdf, vec3(0.5f, 0.5f, 0.51f));
    EXPECT_NE(h, scene_hash(scene, edited, env));
    EnvironmentSettings brighter = env;
    brighter.strength *= 2.f;
    EXPECT_NE(h, scene_hash(scene, scene.materials, brighter));
    Scene moved = scene;
    moved.positions[0].x = std::nextafter(moved.positions[0].x, 1e30f);
    EXPECT_NE(h, scene_hash(moved, scene.materials, env));
    // The fog as traced (the viewer's edit), not only the scene's; no fog hashes as before.
    EXPECT_EQ(h, scene_hash(scene, scene.materials, env, HomogeneousMedium{}));
    EXPECT_NE(h, scene_hash(scene, scene.materials, env, HomogeneousMedium{vec3(0.f), vec3(0.1f), 0.f}));
}

TEST(ShardFormat, ShardsTileTheSampleRange) {
    for (uint32_t total : {1u, 7u, 64u, 100u, 4096u})
        for (uint32_t shards : {1u, 3u, 4u, 7u})
            if (shards <= total) {
                uint64_t next = 0, shortest = total, longest = 0;
                for (uint32_t i = 0; i < shards; ++i) {
                    const SampleRange r = shard_range(i, shards, total);
                    EXPECT_EQ(r.start, next) << total << " " << shards << " " << i;
                    next = r.end();
                    shortest = std::min(shortest, r.count);
                    longest = std::max(longest, r.count);
                }
                EXPECT_EQ(next, total);
                EXPECT_LE(longest - shortest, 1u);
            }
    EXPECT_THROW(shard_range(4, 4, 64), Error);
    EXPECT_THROW(shard_range(0, 8, 4), Error);
}

// Issue 26, defects 1 and 11: --shard is strict decimal, never a wrapped number.
TEST(ShardFormat, ShardTextIsStrict) {
    uint64_t i = 9, n = 9;
    parse_shard("3/16", i, n);
    EXPECT_EQ(i, 3u);
    EXPECT_EQ(n, 16u);
    parse_shard("0/1", i, n);
    EXPECT_EQ(n, 1u);
    for (const char* bad : {"-1/4", "+1/4", " 1/4", "1/4 ", "01/4", "1/04", "4294967296/4294967297",
                            "1/18446744073709551617", "4/4", "0/0", "1/", "/4", "1", "1/4/2", "0x1/4", "1.0/4"}) {
        const std::string text = bad;
        try {
            parse_shard(text, i, n);
            ADD_FAILURE() << "accepted '" << text << "' as " << i << "/" << n;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("expected INDEX/COUNT"), std::string::npos) << e.what();
        }
    }
    // 2^32 shards parse as themselves, and then cannot be filled by any --spp.
    parse_shard("0/4294967296", i, n);
    EXPECT_EQ(n, uint64_t(1) << 32);
    try {
        shard_range(i, n, 64);
        ADD_FAILURE() << "64 samples in 2^32 shards";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("0/4294967296: 64 samples cannot fill 4294967296 shards"),
                  std::string::npos)
            << e.what();
    }
}

TEST(ShardFormat, RangesParseAndJoin) {
    EXPECT_EQ(format_ranges(parse_ranges("16:16,0:16,40:8", "x")), "0:32,40:8");
    for (const char* bad : {"", "5", "1:0", "a:3", "-1:3", "4294967295:2", "0:8,4:8"})
        EXPECT_THROW(parse_ranges(bad, "x"), Error) << bad;
    // Issue 26, defect 11: strict decimal digits and separators.
    for (const char* bad : {"4:+4", " 4:4", "4: 4", "04:4", "4:04", "4:4,", ",4:4", "4:4,,8:1", "4:4 ", "+4:4", "0x4:4",
                            "4:4e0", "4::4", "4:4:4"})
        EXPECT_THROW(parse_ranges(bad, "x"), Error) << bad;
    EXPECT_EQ(format_ranges(parse_ranges("0:1", "x")), "0:1");
    EXPECT_EQ(format_ranges(parse_ranges("0:4294967296", "x")), "0:4294967296");
    // Issue 26, defect 1: 64-bit arithmetic: joined ranges never wrap at 2^32, overflowing text is refused.
    EXPECT_EQ(format_ranges(parse_ranges("4:4294967292,0:4", "x")), "0:4294967296");
    for (const char* bad : {"0:4294967297", "4294967296:1", "18446744073709551615:1", "1:18446744073709551615",
                            "18446744073709551616:1", "4:4294967293"})
        EXPECT_THROW(parse_ranges(bad, "x"), Error) << bad;
}

// Issue 26, defect 1: a merge of 0:4 and 4:4294967292 is 0:4294967296 (not 0:0), and it reads back.
TEST(ShardFormat, RangesJoinedUpToTheIndexLimitReadBack) {
    const TempDir dir;
    Renderer& r = cornell_renderer();
    const PartialRender a = render_part(r, settings_with(SamplerKind::Sobol), 0, 4);
    PartialRender b = render_part(r, settings_with(SamplerKind::Sobol), 4, 1);
    b.ranges = {{4, 4294967292ull}};
    const PartialRender m = merge_partials({a, b}, {"a.exr", "b.exr"});
    EXPECT_EQ(format_ranges(m.ranges), "0:4294967296");
    EXPECT_EQ(m.sample_count(), uint64_t(1) << 32);
    write_partial(dir.file("m.exr"), m);
    EXPECT_EQ(format_ranges(read_partial(dir.file("m.exr")).ranges), "0:4294967296");
}

// Issue 26, defect 8: an attribute string is quoted by a short prefix, not whole.
TEST(ShardBadInput, HugeAttributeStringsAreQuotedShort) {
    const TempDir dir;
    Renderer& r = cornell_renderer();
    PartialRender p = render_part(r, settings_with(SamplerKind::Sobol), 0, 1);
    const PartialRender good = p;
    p.id.settings = std::string(1 << 20, 'x');
    write_partial(dir.file("settings.exr"), p);
    p = good;
    p.id.camera = std::string(1 << 20, 'c');
    write_partial(dir.file("camera.exr"), p);
    p = good;
    p.id.version = std::string(1 << 20, 'v');
    write_partial(dir.file("version.exr"), p);
    for (const char* name : {"settings.exr", "camera.exr", "version.exr"}) {
        std::string message;
        try {
            read_partial(dir.file(name));
        } catch (const Error& e) {
            message = e.what();
        }
        EXPECT_NE(message, "") << name;
        EXPECT_LT(message.size(), 600u) << name;
        EXPECT_NE(message.find("(1048576 bytes)"), std::string::npos) << message.substr(0, 600);
    }
    // Mismatching identities in a merge: both sides quoted short.
    PartialRender q = render_part(r, settings_with(SamplerKind::Sobol), 1, 1);
    PartialRender other = good;
    other.id.camera = std::string(1 << 20, 'c');
    std::string message;
    try {
        merge_partials({other, q}, {"a.exr", "b.exr"});
    } catch (const Error& e) {
        message = e.what();
    }
    EXPECT_NE(message.find("camera"), std::string::npos) << message.substr(0, 600);
    EXPECT_LT(message.size(), 600u);
    EXPECT_EQ(quote_prefix("short"), "'short'");
    EXPECT_EQ(quote_prefix("a\nb"), "'a?b'");
}

// ---------------------------------------------------------------- bad parts

std::string error_of(const std::function<void()>& fn) {
    try {
        fn();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

void expect_one_line_naming(const std::string& message, const std::string& file, const std::string& needle) {
    EXPECT_NE(message, "") << "no error";
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << message;
}

TEST(ShardBadInput, MismatchedAndOverlappingPartsAreRefused) {
    Renderer& r = cornell_renderer();
    const RenderSettings s = settings_with(SamplerKind::Sobol);
    const PartialRender a = render_part(r, s, 0, 2);
    auto merge_error = [&](const PartialRender& b) {
        return error_of([&] { merge_partials({a, b}, {"a.exr", "b.exr"}); });
    };

    expect_one_line_naming(merge_error(render_part(r, s, 1, 2)), "b.exr", "overlaps 0:2 of a.exr");
    expect_one_line_naming(merge_error(render_part(r, settings_with(SamplerKind::Sobol, 1), 2, 2)), "b.exr",
                           "settings");
    expect_one_line_naming(merge_error(render_part(r, settings_with(SamplerKind::Independent), 2, 2)), "b.exr",
                           "sampler=independent");
    expect_one_line_naming(merge_error(render_part(r, s, 2, 2, kW + 1, kH)), "b.exr", "size");
    PartialRender moved = render_part(r, s, 2, 2);
    moved.id.camera = camera_text(CameraDesc{});
    expect_one_line_naming(merge_error(moved), "b.exr", "camera");
    PartialRender other_scene = render_part(r, s, 2, 2);
    other_scene.id.scene_hash ^= 1;
    expect_one_line_naming(merge_error(other_scene), "b.exr", "scene");
    // The order of the arguments does not change which file is named: the later range is.
    expect_one_line_naming(error_of([&] {
                               merge_partials({render_part(r, s, 1, 2), a}, {"b.exr", "a.exr"});
                           }),
                           "b.exr", "overlaps");
}

TEST(ShardBadInput, DamagedForeignAndTruncatedFilesAreRefused) {
    const TempDir dir;
    Renderer& r = cornell_renderer();
    const PartialRender part = render_part(r, settings_with(SamplerKind::Sobol), 0, 2);

    PartialRender other_version = part;
    other_version.id.version = "pathview 0.0, partial format 1";
    write_partial(dir.file("old.exr"), other_version);
    expect_one_line_naming(error_of([&] { read_partial(dir.file("old.exr")); }), dir.file("old.exr"),
                           "written by 'pathview 0.0");

    write_exr(dir.file("plain.exr"), part.film.mean());
    expect_one_line_naming(error_of([&] { read_partial(dir.file("plain.exr")); }), dir.file("plain.exr"),
                           "not a partial render");

    expect_one_line_naming(error_of([&] { read_partial(dir.file("missing.exr")); }), dir.file("missing.exr"),
                           "no such file");

    // Counts beyond the file's sample ranges.
    PartialRender overcounted = part;
    overcounted.ranges = {{0, 1}};
    write_partial(dir.file("over.exr"), overcounted);
    expect_one_line_naming(error_of([&] { read_partial(dir.file("over.exr")); }), dir.file("over.exr"), "damaged");

    // Cut short at several lengths: in the header, in the offset table, in the pixels.
    write_partial(dir.file("whole.exr"), part);
    std::ifstream in(dir.file("whole.exr"), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (double fraction : {0.01, 0.2, 0.5, 0.9, 0.999}) {
        const std::string cut = dir.file("cut.exr");
        std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(double(bytes.size()) * fraction));
        expect_one_line_naming(error_of([&] { read_partial(cut); }), cut, "");
    }
}

}  // namespace
}  // namespace pv
