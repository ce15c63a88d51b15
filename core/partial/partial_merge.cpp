// core/partial/partial_merge.cpp: merging partial renders (see partial_merge.h).
#include "core/partial/partial_merge.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "core/base/error.h"
#include "core/partial/scene_hash.h"

namespace pv {
namespace {

const char* const kSummedKeys[] = {"pathview:seconds", "pathview:rays", "pathview:dropped_samples"};

uint64_t parse_u64(const std::string& s, bool& ok) {
    const std::optional<uint64_t> v = parse_decimal(s);
    ok = v.has_value();
    return v.value_or(0);
}

// The checks of a merge on the parts' headers: same identity, disjoint ranges. Returns the parts' order (by first
// sample index, so the sums do not depend on the order of the arguments) and sets `out`'s identity, ranges, info.
std::vector<size_t> plan_merge(const std::vector<PartialRender>& parts, const std::vector<std::string>& names,
                               PartialRender& out) {
    if (parts.empty()) throw Error("merge: no partial renders given");
    std::vector<size_t> order(parts.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return parts[a].ranges.front().start < parts[b].ranges.front().start; });

    const PartialRender& first = parts[order[0]];
    const std::string& first_name = names[order[0]];
    out.id = first.id;
    out.info = first.info;
    struct Owned {
        SampleRange range;
        size_t part;
    };
    std::vector<Owned> all;
    for (const SampleRange& r : first.ranges) all.push_back({r, order[0]});
    for (size_t k = 1; k < order.size(); ++k) {
        const PartialRender& p = parts[order[k]];
        const std::string& name = names[order[k]];
        auto mismatch = [&](const std::string& what, const std::string& mine, const std::string& theirs) {
            throw Error(name + ": " + what + " " + quote_prefix(mine) + " differs from " + first_name + "'s " +
                        quote_prefix(theirs) + "; parts of one render must agree");
        };
        if (p.id.version != first.id.version) mismatch("version", p.id.version, first.id.version);
        if (p.id.scene_hash != first.id.scene_hash)
            mismatch("scene (geometry, materials, environment) hash", hash_hex(p.id.scene_hash),
                     hash_hex(first.id.scene_hash));
        if (p.id.settings != first.id.settings) mismatch("settings", p.id.settings, first.id.settings);
        if (p.id.camera != first.id.camera) mismatch("camera", p.id.camera, first.id.camera);
        if (p.id.width != first.id.width || p.id.height != first.id.height)
            mismatch("size", std::to_string(p.id.width) + "x" + std::to_string(p.id.height),
                     std::to_string(first.id.width) + "x" + std::to_string(first.id.height));
        for (const SampleRange& r : p.ranges) all.push_back({r, order[k]});
    }
    std::stable_sort(all.begin(), all.end(),
                     [](const Owned& a, const Owned& b) { return a.range.start < b.range.start; });
    for (size_t i = 1; i < all.size(); ++i)
        if (all[i].range.start < all[i - 1].range.end())
            throw Error(names[all[i].part] + ": sample range " + format_ranges({all[i].range}) + " overlaps " +
                        format_ranges({all[i - 1].range}) + " of " + names[all[i - 1].part] +
                        "; each sample index may be merged once");
    for (size_t k = 1; k < order.size(); ++k) add_summed_info(out.info, parts[order[k]].info);
    out.ranges.clear();
    for (const Owned& o : all) out.ranges.push_back(o.range);
    normalize_ranges(out.ranges, "merge");
    return order;
}

// a += b, as Film::merge, refusing (naming `name`, the file of b) a sum that overflows: never a non-finite film.
void add_pixels(FilmPixel* a, const FilmPixel* b, size_t n, size_t first, int w, const std::string& name) {
    for (size_t i = 0; i < n; ++i) {
        FilmPixel& x = a[i];
        const FilmPixel& y = b[i];
        for (int c = 0; c < 3; ++c) {
            x.sum[c] += y.sum[c];
            x.sum_sq[c] += y.sum_sq[c];
            x.sum_even[c] += y.sum_even[c];
        }
        if (uint64_t(x.n) + y.n > UINT32_MAX)
            throw Error(name + ": " + pixel_name(first + i, w) + ": the merged sample count exceeds 2^32 - 1");
        x.n += y.n;
        x.n_even += y.n_even;
        const char* what = "";
        if (!plausible_sums(x, what))
            throw Error(name + ": " + pixel_name(first + i, w) + ": adding this part's " + what +
                        " overflows (not finite or beyond what float samples give); nothing is written");
    }
}

}  // namespace

void add_summed_info(Metadata& into, const Metadata& from) {
    for (const char* key : kSummedKeys) {
        const auto a = into.find(key);
        const auto b = from.find(key);
        if (b == from.end()) continue;
        if (a == into.end()) {
            into[key] = b->second;
            continue;
        }
        bool ok_a = false, ok_b = false;
        const uint64_t ia = parse_u64(a->second, ok_a), ib = parse_u64(b->second, ok_b);
        if (ok_a && ok_b) {
            a->second = std::to_string(ia + ib);
        } else {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.6f", std::atof(a->second.c_str()) + std::atof(b->second.c_str()));
            a->second = buf;
        }
    }
}

PartialRender merge_partials(const std::vector<PartialRender>& parts, const std::vector<std::string>& names) {
    PartialRender out;
    const std::vector<size_t> order = plan_merge(parts, names, out);
    std::vector<FilmPixel> px = parts[order[0]].film.pixels();
    for (size_t k = 1; k < order.size(); ++k)
        add_pixels(px.data(), parts[order[k]].film.pixels().data(), px.size(), 0, out.id.width, names[order[k]]);
    out.film = Film::from_pixels(out.id.width, out.id.height, std::move(px));
    return out;
}

PartialRender merge_partial_files(const std::vector<std::string>& paths,
                                  const std::function<void(int, int)>& before_pixels) {
    // Every header first (identity, ranges, size for the file, the image budget): nothing is allocated for pixels
    // until every part is known to fit.
    std::vector<PartialRender> headers;
    for (const std::string& path : paths) headers.push_back(read_partial_header(path));
    PartialRender out;
    const std::vector<size_t> order = plan_merge(headers, paths, out);
    const int w = out.id.width, h = out.id.height;
    if (before_pixels) before_pixels(w, h);
    // The output film, then each part added block by block in order of its first sample index (as Film::merge).
    std::vector<FilmPixel> px;
    try {
        px.resize(size_t(w) * size_t(h));
    } catch (const std::bad_alloc&) {
        throw Error(paths[order[0]] + ": out of memory for the " + std::to_string(w) + "x" + std::to_string(h) +
                    " merged film (" + std::to_string(sizeof(FilmPixel)) + " bytes a pixel)");
    }
    for (size_t k = 0; k < order.size(); ++k) {
        const std::string& path = paths[order[k]];
        read_partial_blocks(path, headers[order[k]], [&](int y0, const std::vector<FilmPixel>& block) {
            FilmPixel* dst = px.data() + size_t(y0) * size_t(w);
            if (k == 0)
                std::copy(block.begin(), block.end(), dst);
            else
                add_pixels(dst, block.data(), block.size(), size_t(y0) * size_t(w), w, path);
        });
    }
    out.film = Film::from_pixels(w, h, std::move(px));
    return out;
}

}  // namespace pv
