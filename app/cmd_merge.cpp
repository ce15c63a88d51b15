// app/cmd_merge.cpp: `pathview merge OUT PART...`: adds partial renders of one image (core/partial/partial.h) and
// writes the result: an .exr is itself a partial render (mergeable and resumable; its R, G, B are the image), a .png
// the tone-mapped mean. Every part is read and checked before anything is written.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>

#include "app/commands.h"
#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/image/image_io.h"
#include "core/partial/partial.h"
#include "core/partial/partial_merge.h"

namespace pv::app {
namespace {

struct MergeOptions {
    std::string out;
    std::vector<std::string> more_outs;  // every -o
    std::vector<std::string> parts;
    float exposure = 0.f;
    std::string require;  // --require START:COUNT[,...]: the ranges the parts must cover, exactly
    double max_image_megapixels = double(ImageLimits{}.max_pixels) * 1e-6;  // the budget of every image reader
};

bool has_ext(const std::string& path, const char* lower, const char* upper) {
    const std::string ext = std::filesystem::path(path).extension().string();
    return ext == lower || ext == upper;
}

void run(const MergeOptions& o) {
    std::vector<std::string> outs{o.out};
    outs.insert(outs.end(), o.more_outs.begin(), o.more_outs.end());
    for (const std::string& out : outs)
        if (!has_ext(out, ".exr", ".EXR") && !has_ext(out, ".png", ".PNG"))
            throw Error(out + ": unknown image format '" + std::filesystem::path(out).extension().string() +
                        "'; expected .exr or .png");
    for (const std::string& out : outs) check_writable(out);  // every output before reading or writing anything
    const std::string required =
        o.require.empty() ? "" : format_ranges(parse_ranges(o.require, "--require " + quote_prefix(o.require)));
    set_image_limits(ImageLimits{uint64_t(o.max_image_megapixels * 1e6)});
    const PartialRender merged =
        merge_partial_files(o.parts, [&](int w, int h) { check_merge_memory(o.parts.front(), w, h); });
    if (!o.require.empty() && format_ranges(merged.ranges) != required)
        throw Error("--require " + quote_prefix(o.require) + ": the parts hold samples " +
                    format_ranges(merged.ranges) + " (a part is missing or extra)");

    Image image = merged.film.mean();
    for (float& v : image.rgb) {
        // Overflow saturates, as in `render`: the means are finite and non-negative.
        const float scaled = v * std::exp2(o.exposure);
        v = std::isfinite(scaled) ? scaled : std::numeric_limits<float>::max();
    }
    for (const std::string& out : outs) {
        if (has_ext(out, ".exr", ".EXR"))
            write_partial(out, merged);
        else
            write_png(out, image);
    }
    std::printf("pathview: merged %zu parts, samples %s (%llu spp), %dx%d, estimated relMSE %.3g -> %s\n",
                o.parts.size(), format_ranges(merged.ranges).c_str(),
                static_cast<unsigned long long>(merged.sample_count()), merged.id.width, merged.id.height,
                merged.film.estimated_rel_mse(), o.out.c_str());
}

}  // namespace

void add_merge_command(CLI::App& app) {
    auto o = std::make_shared<MergeOptions>();
    CLI::App* cmd = app.add_subcommand(
        "merge",
        "Merge partial renders of one image (pathview render --samples START:COUNT) into OUT: .exr (itself a "
        "partial render: mergeable, resumable, R G B = the image) or .png");
    cmd->add_option("out", o->out, "Output file: .exr or .png")->required();
    cmd->add_option("parts", o->parts,
                    "Partial renders (.exr) of the same scene, settings, camera and size, with "
                    "disjoint sample ranges")
        ->required()
        ->expected(1, -1);
    cmd->add_option("-o,--output", o->more_outs, "A further output file (.exr or .png)")->take_all();
    cmd->add_option("--require", o->require,
                    "Refuse unless the parts hold exactly these sample indices (START:COUNT, e.g. 0:4096): catches a "
                    "missing shard");
    add_image_budget_option(*cmd, o->max_image_megapixels,
                            "Largest partial render read, in megapixels (as render's budget for images); larger parts, "
                            "or parts implausibly small for their size, are refused before any pixel is read");
    add_exposure_option(*cmd, o->exposure, "Exposure in stops for PNG outputs");
    cmd->callback([o] { run(*o); });
}

}  // namespace pv::app
