// core/frame/partial.h: partial renders. A render split by sample index: each process renders the indices
// [start, start + count) (Renderer::set_next_sample) and writes a partial EXR; `pathview merge` adds the parts'
// per-pixel sums, and `pathview render --resume` continues one. Samples depend only on (pixel, index, seed), so
// the merged sums are those of one process rendering every index.
//
// File format (pathview:partial = 1), an ordinary scanline EXR that any viewer shows as the mean image:
//   R, G, B            FLOAT  the mean (what read_exr() returns)
//   sum_hi.R .. sum_lo.B, sumsq_hi.*, sumsq_lo.*, half_hi.*, half_lo.*
//                      UINT   Film's double accumulators (sum, sum of squares, first half-buffer sum) stored
//                             exactly: the high and low 32 bits of each IEEE-754 double. EXR has no double
//                             channels; a float hi + float lo pair keeps only 48 of the 53 significant bits, and a
//                             float mean + count loses the sum's low bits, so neither merges exactly.
//   count.n, count.half UINT  accepted samples per pixel, and of those in the first half-buffer
// String attributes: pathview:version, pathview:scene_hash (content of geometry, materials, textures and
// environment), pathview:settings, pathview:partial:camera (exact), pathview:samples ("0:16,32:16"), pathview:spp,
// pathview:rel_mse_estimate (Film::estimated_rel_mse of the file's sums), plus informational ones (scene path,
// seconds, rays, dropped samples) that a merge sums or keeps.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/base/text.h"
#include "core/image/film.h"
#include "core/image/image_io.h"
#include "core/render/integrator.h"
#include "core/scene/environment.h"

namespace pv {

class Renderer;

// Sample indices [start, start + count), within the sampler's index space [0, 2^32). 64-bit, so that no sum of
// starts and counts wraps (a part claiming 4:4294967292 merged with 0:4 is 0:4294967296, not 0:0).
struct SampleRange {
    uint64_t start = 0;
    uint64_t count = 0;
    uint64_t end() const { return start + count; }
};
constexpr uint64_t kSampleIndexLimit = uint64_t(1) << 32;  // sample indices are below this

// parse_decimal and quote_prefix: core/base/text.h.
// "0:16,32:16"; parse_ranges throws pv::Error ("<what>: ...") on anything else, or on overlapping ranges.
std::string format_ranges(const std::vector<SampleRange>& ranges);
std::vector<SampleRange> parse_ranges(const std::string& text, const std::string& what);
// Sorts by start and joins touching ranges (0:16,16:16 -> 0:32); throws pv::Error naming `what` if two overlap.
void normalize_ranges(std::vector<SampleRange>& ranges, const std::string& what);

// Shard `index` of `shards` of the sample indices [0, total): contiguous ranges in order, the first total % shards
// one sample longer, so that the shards tile [0, total). Throws pv::Error if index >= shards or total < shards.
SampleRange shard_range(uint64_t index, uint64_t shards, uint64_t total);
// "I/N" of --shard, strictly (parse_decimal's rules, N >= 1, I < N); throws pv::Error saying what was expected.
void parse_shard(const std::string& text, uint64_t& index, uint64_t& shards);

// What must agree for two partial renders to merge.
struct RenderIdentity {
    std::string version;  // partial_version() of the pathview that wrote it
    uint64_t scene_hash = 0;
    std::string settings;  // RenderSettings::describe()
    std::string camera;    // camera_text()
    int width = 0, height = 0;
};

struct PartialRender {
    RenderIdentity id;
    std::vector<SampleRange> ranges;  // sorted, disjoint, touching ones joined (normalize_ranges)
    Film film;
    Metadata info;  // other pathview:* attributes (scene path, seconds, rays, dropped samples, environment)

    uint64_t sample_count() const;  // sum of the ranges' counts
};

// "pathview 0.1, partial format 1": written to and required of every partial file.
std::string partial_version();

// Content hash of what the renderer draws from: triangles, normals, UVs, material ids, materials as edited,
// textures (including the environment map) and the environment's settings. Not the file names.
uint64_t scene_hash(const Scene& scene, const std::vector<Material>& materials, const EnvironmentSettings& env);

// The camera as exact render flags ("--eye x,y,z ... --focus-distance d", %.9g) and back. parse_camera throws
// pv::Error naming `what` on malformed text.
std::string camera_text(const CameraDesc& camera);
CameraDesc parse_camera(const std::string& text, const std::string& what);
// RenderSettings::describe() back to settings; throws pv::Error naming `what` unless describe() of the result
// gives `text` again.
RenderSettings parse_settings(const std::string& text, const std::string& what);

// The renderer's film and identity as a partial render of `ranges`, with render_metadata() as info.
PartialRender partial_from_renderer(const Renderer& renderer, std::vector<SampleRange> ranges);

// Writes a partial EXR (temporary file, then rename). Throws pv::Error naming `path`.
void write_partial(const std::string& path, const PartialRender& part);
// Reads and validates a partial EXR: format and version, every channel, the identity attributes, the size for the
// file (at most 12 pixels a byte), counts within the sample ranges, and sums that float samples can give (finite,
// non-negative, at most n times the largest float: every statistic of the film stays finite). Throws pv::Error with
// one line naming `path`.
PartialRender read_partial(const std::string& path);

// Merges parts of one render (names[i] is parts[i]'s file, for messages): same version, scene hash, settings,
// camera and size, disjoint sample ranges; the sums are added pixel by pixel (as Film::merge) in order of the
// parts' first sample index, and the numeric info (seconds, rays, dropped samples) is summed. Throws pv::Error
// naming the file that does not fit and why, or whose sums would overflow (never a non-finite film).
PartialRender merge_partials(const std::vector<PartialRender>& parts, const std::vector<std::string>& names);
// The same merge of partial EXR files, streamed: every header is read and checked first (the image budget, the
// size for the file), then each part's pixels are added in blocks of rows: memory is the output film plus a block.
// `before_pixels(width, height)`, when given, runs once every header has passed, before the output film is allocated
// (the app's memory check).
PartialRender merge_partial_files(const std::vector<std::string>& paths,
                                  const std::function<void(int, int)>& before_pixels = nullptr);
// Adds the numeric info that a merge sums (seconds, rays, dropped samples) of `from` into `into`.
void add_summed_info(Metadata& into, const Metadata& from);

}  // namespace pv
