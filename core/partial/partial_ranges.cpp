// core/partial/partial_ranges.cpp: sample ranges and shards (see partial_ranges.h).
#include "core/partial/partial_ranges.h"

#include <algorithm>

#include "core/base/error.h"

namespace pv {

std::string format_ranges(const std::vector<SampleRange>& ranges) {
    std::string s;
    for (const SampleRange& r : ranges)
        s += (s.empty() ? "" : ",") + std::to_string(r.start) + ":" + std::to_string(r.count);
    return s;
}

void normalize_ranges(std::vector<SampleRange>& ranges, const std::string& what) {
    std::sort(ranges.begin(), ranges.end(),
              [](const SampleRange& a, const SampleRange& b) { return a.start < b.start; });
    std::vector<SampleRange> out;
    for (const SampleRange& r : ranges) {
        if (!out.empty() && r.start < out.back().end())
            throw Error(what + ": sample ranges " + format_ranges({out.back()}) + " and " + format_ranges({r}) +
                        " overlap");
        if (!out.empty() && r.start == out.back().end())
            out.back().count += r.count;
        else
            out.push_back(r);
    }
    ranges = std::move(out);
}

std::vector<SampleRange> parse_ranges(const std::string& text, const std::string& what) {
    std::vector<SampleRange> out;
    size_t pos = 0;
    while (!text.empty()) {
        const size_t comma = text.find(',', pos);
        const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
        const size_t colon = item.find(':');
        const std::optional<uint64_t> a =
            colon == std::string::npos ? std::nullopt : parse_decimal(item.substr(0, colon), kSampleIndexLimit);
        const std::optional<uint64_t> b =
            colon == std::string::npos ? std::nullopt : parse_decimal(item.substr(colon + 1), kSampleIndexLimit);
        if (!a || !b || *b == 0 || *a + *b > kSampleIndexLimit)
            throw Error(what + ": sample range " + quote_prefix(item) +
                        "; expected START:COUNT (decimal digits, no sign, spaces or leading zeros) with COUNT > 0 "
                        "and START + COUNT <= 2^32, ranges separated by single commas");
        out.push_back({*a, *b});
        if (comma == std::string::npos) break;
        pos = comma + 1;
    }
    if (out.empty()) throw Error(what + ": no sample range; expected START:COUNT[,START:COUNT...]");
    normalize_ranges(out, what);
    return out;
}

void parse_shard(const std::string& text, uint64_t& index, uint64_t& shards) {
    const size_t slash = text.find('/');
    const std::optional<uint64_t> i =
        slash == std::string::npos ? std::nullopt : parse_decimal(text.substr(0, slash), kSampleIndexLimit);
    const std::optional<uint64_t> n =
        slash == std::string::npos ? std::nullopt : parse_decimal(text.substr(slash + 1), kSampleIndexLimit);
    if (!i || !n || *n == 0 || *i >= *n)
        throw Error("--shard " + quote_prefix(text) +
                    ": expected INDEX/COUNT in decimal digits (no sign, spaces or leading zeros) with "
                    "0 <= INDEX < COUNT, e.g. 3/16");
    index = *i;
    shards = *n;
}

SampleRange shard_range(uint64_t index, uint64_t shards, uint64_t total) {
    if (shards == 0 || index >= shards)
        throw Error("--shard " + std::to_string(index) + "/" + std::to_string(shards) +
                    ": expected INDEX/COUNT with 0 <= INDEX < COUNT");
    if (total < shards)
        throw Error("--shard " + std::to_string(index) + "/" + std::to_string(shards) + ": " + std::to_string(total) +
                    " samples cannot fill " + std::to_string(shards) + " shards; use at most " + std::to_string(total) +
                    " shards");
    const uint64_t base = total / shards, extra = total % shards;
    return {index * base + std::min(index, extra), base + (index < extra ? 1u : 0u)};
}

}  // namespace pv
