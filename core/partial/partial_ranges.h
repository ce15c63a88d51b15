// core/partial/partial_ranges.h: the sample-index ranges of partial renders ("0:16,32:16") and the shards of
// --shard I/N, parsed strictly (core/base/text.h's decimals) and written back.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/text.h"

namespace pv {

// Sample indices [start, start + count), within the sampler's index space [0, 2^32). 64-bit, so that no sum of
// starts and counts wraps (a part claiming 4:4294967292 merged with 0:4 is 0:4294967296, not 0:0).
struct SampleRange {
    uint64_t start = 0;
    uint64_t count = 0;
    uint64_t end() const { return start + count; }
};
constexpr uint64_t kSampleIndexLimit = uint64_t(1) << 32;  // sample indices are below this

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

}  // namespace pv
