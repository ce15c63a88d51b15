// core/partial/partial.cpp: the partial-render EXR (OpenEXR UINT channels for the exact double sums) and its
// validation. The identity's text is in render_identity.cpp, the scene hash in scene_hash.cpp, the sample ranges in
// partial_ranges.cpp and the merge in partial_merge.cpp.
#include "core/partial/partial.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <set>

#include "core/base/error.h"
#include "core/image/exr_io.h"

namespace pv {
namespace {

const char* const kRgb[3] = {"R", "G", "B"};

// The three double accumulators of a FilmPixel, by layer name.
using Triple = double[3];
struct Plane {
    const char* layer;
    Triple FilmPixel::*field;
};
const Plane kPlanes[] = {{"sum", &FilmPixel::sum}, {"sumsq", &FilmPixel::sum_sq}, {"half", &FilmPixel::sum_even}};
struct CountPlane {
    const char* name;
    uint32_t FilmPixel::*field;
};
const CountPlane kCounts[] = {{"count.n", &FilmPixel::n}, {"count.half", &FilmPixel::n_even}};

// Attributes that make up the identity or are computed on writing; everything else is info.
const std::set<std::string> kReservedKeys = {"pathview:partial",  "pathview:version",         "pathview:scene_hash",
                                             "pathview:settings", "pathview:partial:camera",  "pathview:samples",
                                             "pathview:spp",      "pathview:rel_mse_estimate"};

// One line: OpenEXR messages may span several.
std::string one_line(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    return s;
}

// Rows per block when reading and writing the pixel planes: memory in proportion to a block, not the image.
constexpr int kBlockRows = 64;

// The UINT channels, in the order of the word planes: each plane's hi and lo words per channel, then the counts.
std::vector<std::string> word_channel_names() {
    std::vector<std::string> names;
    for (const Plane& plane : kPlanes)
        for (int c = 0; c < 3; ++c)
            for (const char* half : {"_hi.", "_lo."}) names.push_back(std::string(plane.layer) + half + kRgb[c]);
    for (const CountPlane& cp : kCounts) names.push_back(cp.name);
    return names;
}

// The largest value one accepted sample adds to a sum (Film::add takes finite float radiance).
constexpr double kMaxSample = double(FLT_MAX) * (1.0 + 1e-9);  // with room for the double sums' rounding

// The header of an opened partial EXR, checked: identity, ranges, info, channels, compression, size for the file.
PartialRender read_header(const std::string& path, Imf::InputFile& file) {
    PartialRender part;
    const Imf::Header& header = file.header();
    Metadata attrs;
    for (auto it = header.begin(); it != header.end(); ++it)
        if (auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) attrs[it.name()] = s->value();
    auto attr = [&](const char* key) {
        const auto it = attrs.find(key);
        if (it == attrs.end()) throw Error(path + ": attribute " + key + " is missing; the file is damaged");
        return it->second;
    };
    if (!attrs.count("pathview:partial"))
        throw Error(path +
                    ": not a partial render (no pathview:partial attribute); expected a file written by "
                    "`pathview render --samples`, `--resume` or `pathview merge`");
    if (attrs["pathview:partial"] != kPartialFormat || attr("pathview:version") != partial_version())
        throw Error(path + ": written by " + quote_prefix(attrs["pathview:version"]) + " (format " +
                    quote_prefix(attrs["pathview:partial"]) + "); this is " + partial_version() +
                    ", which reads only its own partial renders");

    const Imath::Box2i dw = header.dataWindow();
    const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
    if (dw.min.x != 0 || dw.min.y != 0 || w <= 0 || h <= 0 || w * h > (1l << 28))
        throw Error(path + ": data window is not [0, w) x [0, h) or is too large");
    // pathview writes ZIP; these compress the 92 bytes of a pixel's 23 channels at most 1032:1 (zlib's limit).
    const Imf::Compression compression = header.compression();
    if (compression != Imf::NO_COMPRESSION && compression != Imf::RLE_COMPRESSION &&
        compression != Imf::ZIPS_COMPRESSION && compression != Imf::ZIP_COMPRESSION)
        throw Error(path + ": compression " + std::to_string(int(compression)) +
                    " in a partial render; expected none, RLE, ZIPS or ZIP (pathview writes ZIP)");
    std::error_code ec;
    const uint64_t bytes = std::filesystem::file_size(path, ec);
    if (!ec && double(w) * double(h) > double(bytes) * 12.0 + 65536.0)
        throw Error(path + ": declares " + std::to_string(w) + "x" + std::to_string(h) + " pixels but has only " +
                    std::to_string(bytes) +
                    " bytes (a partial render holds at least 1 byte per 12 pixels); the file is damaged or "
                    "truncated");
    part.id.version = attrs["pathview:version"];
    const std::string hash = attr("pathview:scene_hash");
    part.id.scene_hash = std::strtoull(hash.c_str(), nullptr, 16);
    if (hash.size() != 16 || hash.find_first_not_of("0123456789abcdef") != std::string::npos)
        throw Error(path + ": pathview:scene_hash " + quote_prefix(hash) + " is not 16 hex digits");
    part.id.settings = attr("pathview:settings");
    parse_settings(part.id.settings, path);
    part.id.camera = attr("pathview:partial:camera");
    parse_camera(part.id.camera, path);
    part.id.width = int(w);
    part.id.height = int(h);
    part.ranges = parse_ranges(attr("pathview:samples"), path);
    for (const auto& [k, v] : attrs)
        if (!kReservedKeys.count(k)) part.info[k] = v;
    for (const std::string& name : word_channel_names()) {
        const Imf::Channel* ch = header.channels().findChannel(name);
        if (!ch || ch->type != Imf::UINT) throw Error(path + ": channel " + name + " is missing or not UINT");
    }
    return part;
}

// Reads rows [y0, y1) of an opened partial EXR (checked by read_header) into `px` (w * (y1 - y0) pixels) and
// checks every pixel against the file's sample count. `words` is scratch space, reused between blocks.
void read_rows(const std::string& path, Imf::InputFile& file, const PartialRender& header, int y0, int y1,
               std::vector<std::vector<uint32_t>>& words, std::vector<FilmPixel>& px) {
    const int w = header.id.width;
    const size_t n = size_t(w) * size_t(y1 - y0);
    const std::vector<std::string> names = word_channel_names();
    words.resize(names.size());
    Imf::FrameBuffer fb;
    for (size_t k = 0; k < names.size(); ++k) {
        words[k].resize(n);
        fb.insert(names[k], Imf::Slice::Make(Imf::UINT, words[k].data(), Imath::V2i(0, y0), w, y1 - y0,
                                             sizeof(uint32_t), sizeof(uint32_t) * size_t(w)));
    }
    file.setFrameBuffer(fb);
    file.readPixels(y0, y1 - 1);
    if (y1 == header.id.height && !file.isComplete()) throw Error(path + ": the file is truncated");

    px.assign(n, FilmPixel{});
    size_t k = 0;
    for (const Plane& plane : kPlanes)
        for (int c = 0; c < 3; ++c, k += 2)
            for (size_t i = 0; i < n; ++i) {
                const uint64_t bits = (uint64_t(words[k][i]) << 32) | words[k + 1][i];
                std::memcpy(&(px[i].*plane.field)[c], &bits, 8);
            }
    for (const CountPlane& cp : kCounts) {
        for (size_t i = 0; i < n; ++i) px[i].*cp.field = words[k][i];
        ++k;
    }
    const uint64_t total = header.sample_count();
    const size_t first = size_t(y0) * size_t(w);
    for (size_t i = 0; i < n; ++i) {
        if (px[i].n > total || px[i].n_even > px[i].n)
            throw Error(path + ": " + pixel_name(first + i, w) + " counts " + std::to_string(px[i].n) + " samples (" +
                        std::to_string(px[i].n_even) + " in the first half), more than its " + std::to_string(total) +
                        "; the file is damaged");
        const char* what = "";
        if (!plausible_sums(px[i], what))
            throw Error(path + ": " + pixel_name(first + i, w) + " has a " + what +
                        " that is negative, not finite or larger than its " + std::to_string(px[i].n) +
                        " samples of finite float radiance can give; the file is damaged");
    }
}

// OpenEXR's exceptions as one line naming `path`.
template <class Fn>
void guarded(const std::string& path, Fn&& fn) {
    try {
        read_exr_guarded(path, fn, "a partial render EXR");
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(path + ": out of memory while reading the partial render");
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read EXR: " + one_line(e.what()));
    }
}

}  // namespace

// Whether a pixel's accumulators are what `n` float samples can give: finite, non-negative, each sum at most n
// (n_even) times the largest float, and nothing without samples. Within these bounds every statistic the film
// derives (float mean, variance, half-buffer error estimate) is finite, and so is any sum of merged parts.
bool plausible_sums(const FilmPixel& px, const char*& what) {
    for (int c = 0; c < 3; ++c) {
        const double v[3] = {px.sum[c], px.sum_sq[c], px.sum_even[c]};
        for (int k = 0; k < 3; ++k)
            if (!(std::isfinite(v[k]) && v[k] >= 0.0)) {
                what = kPlanes[k].layer;
                return false;
            }
        if (px.sum[c] > kMaxSample * px.n || px.sum_even[c] > kMaxSample * px.n_even) {
            what = px.sum[c] > kMaxSample * px.n ? "sum" : "half";
            return false;
        }
        if (px.sum_sq[c] > kMaxSample * kMaxSample * px.n) {
            what = "sumsq";
            return false;
        }
    }
    return true;
}

std::string pixel_name(size_t i, int w) {
    return "pixel (" + std::to_string(i % size_t(w)) + ", " + std::to_string(i / size_t(w)) + ")";
}

uint64_t PartialRender::sample_count() const {
    uint64_t n = 0;
    for (const SampleRange& r : ranges) n += r.count;
    return n;
}

PartialRender make_partial(RenderIdentity id, std::vector<SampleRange> ranges, const Film& film, Metadata info) {
    PartialRender p;
    p.id = std::move(id);
    normalize_ranges(ranges, "partial render");
    p.ranges = std::move(ranges);
    p.film = film;
    p.info = std::move(info);
    for (const std::string& k : kReservedKeys) p.info.erase(k);
    p.info.erase("pathview:threads");  // differs between parts and means nothing for the sum
    return p;
}

void write_partial(const std::string& path, const PartialRender& part) {
    const Film& film = part.film;
    const int w = film.width(), h = film.height();
    const std::vector<FilmPixel>& px = film.pixels();
    const std::vector<std::string> names = word_channel_names();

    Metadata attrs = part.info;
    attrs["pathview:partial"] = kPartialFormat;
    attrs["pathview:version"] = part.id.version;
    attrs["pathview:scene_hash"] = hash_hex(part.id.scene_hash);
    attrs["pathview:settings"] = part.id.settings;
    attrs["pathview:partial:camera"] = part.id.camera;
    attrs["pathview:samples"] = format_ranges(part.ranges);
    attrs["pathview:spp"] = std::to_string(part.sample_count());
    char rel[32];
    std::snprintf(rel, sizeof rel, "%.6g", film.estimated_rel_mse());
    attrs["pathview:rel_mse_estimate"] = rel;

    Imf::Header header(w, h);
    for (const char* c : kRgb) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    for (const std::string& name : names) header.channels().insert(name, Imf::Channel(Imf::UINT));
    for (const auto& [k, v] : attrs) header.insert(k, Imf::StringAttribute(v));
    write_exr_atomically(path, header, [&](Imf::OutputFile& file) {
        // Row blocks: the mean as FLOAT (as Film::mean), each double as its high and low 32-bit words, the counts.
        std::vector<float> rgb;
        std::vector<std::vector<uint32_t>> words(names.size());
        for (int y0 = 0; y0 < h; y0 += kBlockRows) {
            const int rows = std::min(kBlockRows, h - y0);
            const size_t n = size_t(w) * size_t(rows), first = size_t(y0) * size_t(w);
            rgb.resize(3 * n);
            for (auto& v : words) v.resize(n);
            for (size_t i = 0; i < n; ++i) {
                const FilmPixel& p = px[first + i];
                const double inv = p.n ? 1.0 / p.n : 0.0;
                for (int c = 0; c < 3; ++c) rgb[3 * i + c] = static_cast<float>(p.sum[c] * inv);
                size_t k = 0;
                for (const Plane& plane : kPlanes)
                    for (int c = 0; c < 3; ++c, k += 2) {
                        uint64_t bits;
                        std::memcpy(&bits, &(p.*plane.field)[c], 8);
                        words[k][i] = uint32_t(bits >> 32);
                        words[k + 1][i] = uint32_t(bits);
                    }
                for (const CountPlane& cp : kCounts) words[k++][i] = p.*cp.field;
            }
            Imf::FrameBuffer fb;
            for (int c = 0; c < 3; ++c)
                fb.insert(kRgb[c], Imf::Slice::Make(Imf::FLOAT, rgb.data() + c, Imath::V2i(0, y0), w, rows,
                                                    3 * sizeof(float), 3 * sizeof(float) * size_t(w)));
            for (size_t k = 0; k < names.size(); ++k)
                fb.insert(names[k], Imf::Slice::Make(Imf::UINT, words[k].data(), Imath::V2i(0, y0), w, rows,
                                                     sizeof(uint32_t), sizeof(uint32_t) * size_t(w)));
            file.setFrameBuffer(fb);
            file.writePixels(rows);
        }
    });
}

PartialRender read_partial(const std::string& path) {
    PartialRender part;
    guarded(path, [&](Imf::InputFile& file) {
        part = read_header(path, file);
        std::vector<std::vector<uint32_t>> words;
        std::vector<FilmPixel> px, block;
        px.reserve(size_t(part.id.width) * size_t(part.id.height));
        for (int y0 = 0; y0 < part.id.height; y0 += kBlockRows) {
            read_rows(path, file, part, y0, std::min(part.id.height, y0 + kBlockRows), words, block);
            px.insert(px.end(), block.begin(), block.end());
        }
        part.film = Film::from_pixels(part.id.width, part.id.height, std::move(px));
    });
    return part;
}

PartialRender read_partial_header(const std::string& path) {
    PartialRender part;
    guarded(path, [&](Imf::InputFile& file) { part = read_header(path, file); });
    return part;
}

void read_partial_blocks(const std::string& path, const PartialRender& header,
                         const std::function<void(int, const std::vector<FilmPixel>&)>& block) {
    guarded(path, [&](Imf::InputFile& file) {
        std::vector<std::vector<uint32_t>> words;
        std::vector<FilmPixel> px;
        for (int y0 = 0; y0 < header.id.height; y0 += kBlockRows) {
            read_rows(path, file, header, y0, std::min(header.id.height, y0 + kBlockRows), words, px);
            block(y0, px);
        }
    });
}

}  // namespace pv
