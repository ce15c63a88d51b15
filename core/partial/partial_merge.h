// core/partial/partial_merge.h: `pathview merge`: partial renders of one image (same identity, disjoint sample
// ranges) added into one, in memory or streamed from their files.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/partial/partial.h"

namespace pv {

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
