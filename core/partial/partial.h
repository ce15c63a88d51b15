// core/partial/partial.h: partial renders. A render split by sample index: each process renders the indices
// [start, start + count) and writes a partial EXR; `pathview merge` adds the parts' per-pixel sums, and `pathview
// render --resume` continues one. Samples depend only on (pixel, index, seed), so the merged sums are exact.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/base/text.h"
#include "core/image/film.h"
#include "core/image/image_io.h"
#include "core/partial/partial_ranges.h"
#include "core/partial/render_identity.h"
#include "core/partial/scene_hash.h"
#include "core/render/integrator.h"
#include "core/scene/environment.h"

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
//
// The concerns live beside this file: the sample ranges (partial_ranges.h), the identity's text: version, settings,
// camera (render_identity.h), the scene hash (scene_hash.h) and the merge (partial_merge.h). This header includes
// all but the merge.

namespace pv {

struct PartialRender {
    RenderIdentity id;
    std::vector<SampleRange> ranges;  // sorted, disjoint, touching ones joined (normalize_ranges)
    Film film;
    Metadata info;  // other pathview:* attributes (scene path, seconds, rays, dropped samples, environment)

    uint64_t sample_count() const;  // sum of the ranges' counts
};

// A partial render of `ranges` (normalised) with identity `id`, a copy of `film` and `info` without the keys the
// format reserves and without pathview:threads (differs between parts and means nothing for the sum). The renderer's
// own: partial_from_renderer (core/frame/renderer_partial.h).
PartialRender make_partial(RenderIdentity id, std::vector<SampleRange> ranges, const Film& film, Metadata info);

// Writes a partial EXR (temporary file, then rename). Throws pv::Error naming `path`.
void write_partial(const std::string& path, const PartialRender& part);
// The header of a partial EXR, read and checked as read_partial checks it (identity, ranges, channels, size for
// the file); no pixels. Throws pv::Error with one line naming `path`.
PartialRender read_partial_header(const std::string& path);
// The pixels of the partial EXR `path`, whose header is `header` (read_partial_header), in blocks of rows checked as
// read_partial checks them: block(y0, pixels of rows y0 ...) for each block in order; memory is one block.
void read_partial_blocks(const std::string& path, const PartialRender& header,
                         const std::function<void(int, const std::vector<FilmPixel>&)>& block);
// Whether a pixel's accumulators are what its float samples can give: finite, non-negative, each sum at most n
// (n_even) times the largest float, and nothing without samples; else false with the plane's name in `what`.
bool plausible_sums(const FilmPixel& px, const char*& what);
// "pixel (x, y)" of pixel index i in a row of w.
std::string pixel_name(size_t i, int w);
// Reads and validates a partial EXR: format and version, every channel, the identity attributes, the size for the
// file (at most 12 pixels a byte), counts within the sample ranges, and sums that float samples can give (finite,
// non-negative, at most n times the largest float: every statistic of the film stays finite). Throws pv::Error with
// one line naming `path`.
PartialRender read_partial(const std::string& path);

}  // namespace pv
