// core/scene/texture_decode.cpp: untrusted image files into Textures (Texture::load, Texture::decode), and texture
// file names resolved (resolve_texture_path).
// stb_image 2.27 (Debian 12) has no limits of its own and loops forever on some Radiance RLE data; it is guarded
// here rather than replaced (OpenImageIO 2.4 would be the alternative): the faults are narrow and known, the guards
// (declared size read first, the RLE walk, truncation found from stb's read position) are small and fuzzed
// (tests/fuzz/fuzz_image.cpp), and OpenImageIO would add a large dependency tree to every build and CI run.
#include "core/scene/texture_decode.h"

#include <stb_image.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/image/image_io.h"

namespace pv {
namespace {

enum class Format { Png, Jpeg, Gif, Bmp, Psd, Pic, Pnm, Hdr, Exr, Other };

bool starts_with(const std::string& s, const char* magic, size_t n) {
    return s.size() >= n && s.compare(0, n, magic, n) == 0;
}

Format sniff(const std::string& b) {
    if (starts_with(b, "\x89PNG\r\n\x1a\n", 8)) return Format::Png;
    if (starts_with(b, "\xff\xd8\xff", 3)) return Format::Jpeg;
    if (starts_with(b, "GIF87a", 6) || starts_with(b, "GIF89a", 6)) return Format::Gif;
    if (starts_with(b, "BM", 2)) return Format::Bmp;
    if (starts_with(b, "8BPS", 4)) return Format::Psd;
    if (starts_with(b, "\x53\x80\xf6\x34", 4)) return Format::Pic;
    if (starts_with(b, "P5", 2) || starts_with(b, "P6", 2)) return Format::Pnm;
    if (starts_with(b, "#?RADIANCE\n", 11) || starts_with(b, "#?RGBE\n", 7)) return Format::Hdr;
    if (starts_with(b, "\x76\x2f\x31\x01", 4)) return Format::Exr;
    return Format::Other;  // TGA has no magic number
}

// The most pixels one byte of a file can hold in each format, from its densest encoding: PNG deflate (1032:1) of
// 1-bit rows; JPEG about 2 bits per 8x8 block of 4:2:0; GIF 12-bit LZW codes of up to 4096 pixels; BMP 1 bit a
// pixel (stb reads no RLE BMP); TGA and PSD run-length packets of 128 pixels in 2 bytes; binary PNM (P5/P6) a byte
// or more a pixel; Radiance RLE 127 pixels per 2 bytes in each of 4 channels. Softimage PIC and TGA, which has no
// magic number to tell it by, get the loosest bound.
double pixels_per_byte(Format f) {
    switch (f) {
        case Format::Png:
            return 8.0 * 1032.0;
        case Format::Jpeg:
            return 1024.0;
        case Format::Gif:
            return 4096.0;
        case Format::Bmp:
            return 8.0;
        case Format::Psd:
            return 128.0;
        case Format::Pnm:
            return 1.0;
        case Format::Hdr:
            return 16.0;
        case Format::Exr:
            return kExrPixelsPerByte;
        default:
            return 4096.0;
    }
}

// stb_image's failure strings are terse ("bad png sig") and, for some inputs, empty: a readable reason.
std::string readable_reason(const char* stb) {
    const std::string r = stb ? stb : "";
    if (r == "unknown image type")
        return "unknown or unsupported image format; expected PNG, JPEG, TGA, BMP, PSD, GIF, PNM (P5/P6), HDR or EXR";
    if (r == "outofmem") return "out of memory";
    bool printable = !r.empty();
    for (unsigned char c : r) printable = printable && c >= 0x20 && c < 0x7f;
    return printable ? "corrupt or unsupported image data (" + r + ")" : "corrupt or unsupported image data";
}

// A Radiance .hdr walked the way stb_image 2.27 decodes it, before stb sees it. stb loops forever on an RLE count
// byte of 0 and at the end of data inside an RLE scanline (it reads zeros past the end, and a zero count makes no
// progress), so both are refused here; stb's own errors (a run past the scanline's end) are refused with a
// clearer message. Sets `truncated` when flat (non-RLE) data ends early, which stb decodes as black.
void validate_hdr(const std::string& path, const std::string& b, bool& truncated) {
    const auto* p = reinterpret_cast<const unsigned char*>(b.data());
    const size_t n = b.size();
    size_t pos = 0;
    auto line = [&](std::string& out) {
        const size_t end = b.find('\n', pos);
        if (end == std::string::npos) return false;
        out = b.substr(pos, std::min<size_t>(end - pos, 1023));
        pos = end + 1;
        return true;
    };
    std::string l;
    bool rgbe = false;
    line(l);
    for (;;) {
        if (!line(l)) throw Error(path + ": truncated Radiance HDR header (no blank line before the resolution)");
        if (l.empty()) break;
        if (l == "FORMAT=32-bit_rle_rgbe") rgbe = true;
    }
    if (!rgbe) throw Error(path + ": unsupported Radiance HDR format; expected FORMAT=32-bit_rle_rgbe");
    if (!line(l)) {  // no newline after the resolution: no pixel data (stb reads zeros)
        l = b.substr(pos, 1023);
        pos = n;
    }
    long h = 0, w = 0;
    char* end = nullptr;
    if (l.compare(0, 3, "-Y ") != 0)
        throw Error(path + ": unsupported Radiance HDR layout; expected -Y height +X width");
    h = std::strtol(l.c_str() + 3, &end, 10);
    while (*end == ' ') ++end;
    if (std::strncmp(end, "+X ", 3) != 0)
        throw Error(path + ": unsupported Radiance HDR layout; expected -Y height +X width");
    w = std::strtol(end + 3, nullptr, 10);
    check_declared_size(path, w, h, n, pixels_per_byte(Format::Hdr));
    const uint64_t flat_bytes = 4ull * uint64_t(w) * uint64_t(h);
    if (w < 8 || w >= 32768) {
        truncated = n - pos < flat_bytes;
        return;
    }
    for (long j = 0; j < h; ++j) {
        if (pos + 4 > n) {
            truncated = true;  // stb decodes the rest as flat zero pixels
            return;
        }
        if (p[pos] != 2 || p[pos + 1] != 2 || (p[pos + 2] & 0x80)) {
            // Not RLE: stb decodes everything from here on as flat pixels, restarting at the first one.
            truncated = n - pos < flat_bytes;
            return;
        }
        const long len = long(p[pos + 2]) << 8 | p[pos + 3];
        if (len != w)
            throw Error(path + ": corrupt Radiance HDR: scanline " + std::to_string(j) + " has length " +
                        std::to_string(len) + "; expected " + std::to_string(w));
        pos += 4;
        for (int k = 0; k < 4; ++k)
            for (long i = 0; i < w;) {
                auto ends = [&] {
                    return Error(path + ": truncated Radiance HDR: the data ends in scanline " + std::to_string(j + 1) +
                                 " of " + std::to_string(h));
                };
                if (pos >= n) throw ends();
                int count = p[pos++];
                const bool run = count > 128;
                if (run) count -= 128;
                if (count == 0)
                    throw Error(path + ": corrupt Radiance HDR: a run-length count of 0 in scanline " +
                                std::to_string(j + 1));
                if (count > w - i)
                    throw Error(path + ": corrupt Radiance HDR: a run passes the end of scanline " +
                                std::to_string(j + 1));
                const size_t need = run ? 1 : size_t(count);
                if (pos + need > n) throw ends();
                pos += need;
                i += count;
            }
    }
}

struct StbFree {
    void operator()(void* p) const { stbi_image_free(p); }
};

// Bytes past the file's end given to stb: it reads zeros past the end of data anyway, and the position it stops
// at tells whether it needed bytes the file lacks (truncated).
constexpr size_t kPadding = 64;

// EXR radiance as texels: negative and non-finite values set to 0 (the constructor), alpha 1.
Texture from_exr_texels(std::vector<vec4> texels, int w, int h) {
    for (vec4& t : texels) t.w = 1.f;
    return Texture(w, h, std::move(texels));
}

}  // namespace

Texture Texture::load(const std::string& path, bool alpha_only, std::vector<std::string>* warnings) {
    const char* what = "an image (PNG, JPEG, TGA, BMP, PSD, GIF, PNM, HDR or EXR)";
    // An EXR is read by OpenEXR from the file, not copied into memory first.
    if (sniff(read_regular_file_prefix(path, 4, what)) == Format::Exr) {
        int w = 0, h = 0;
        std::vector<vec4> texels = read_exr_rgba(path, w, h);
        return from_exr_texels(std::move(texels), w, h);
    }
    // The largest file the budget can need: 16 bytes a pixel (16-bit RGBA PSD/PNM) and headers.
    const uint64_t max_bytes = image_limits().max_pixels * 16 + (uint64_t(64) << 20);
    return decode(read_regular_file(path, max_bytes, what), path, alpha_only, warnings);
}

Texture Texture::decode(std::string bytes, const std::string& path, bool alpha_only,
                        std::vector<std::string>* warnings) {
    const Format format = sniff(bytes);
    std::vector<vec4> texels;
    int w = 0, h = 0, n = 0;
    auto warn = [&](const std::string& what) {
        if (warnings) warnings->push_back(path + ": " + what);
    };
    if (format == Format::Exr) {
        texels = decode_exr_rgba(bytes, path, w, h);
        return from_exr_texels(std::move(texels), w, h);
    }
    if (bytes.size() > size_t(std::numeric_limits<int>::max() - int(kPadding)))
        throw Error(path + ": the file is too large for stb_image (2 GiB)");
    bool truncated = false;
    auto finish = [&](Texture t) {
        if (truncated) warn("the image data ends early (truncated file?); missing pixels are black");
        return t;
    };
    if (format == Format::Hdr) validate_hdr(path, bytes, truncated);
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    if (!stbi_info_from_memory(data, int(bytes.size()), &w, &h, &n))
        throw Error(path + ": cannot read image: " + readable_reason(stbi_failure_reason()));
    check_declared_size(path, w, h, bytes.size(), pixels_per_byte(format));
    // stb_image 2.27's 16-bit PNM reader crashed (SEGV inside stbi_load_from_file) on a truncated 153-byte P5 file
    // found by fuzz_image (tests/fuzz/corpus-image/regression_pnm16_truncated.pgm): refuse 16-bit PNM up front.
    if (format == Format::Pnm && stbi_is_16_bit_from_memory(data, int(bytes.size())))
        throw Error(path + ": 16-bit PGM/PPM (maxval above 255) is not supported; convert it to 8 bits, PNG or EXR");

    if (format == Format::Hdr) {
        std::unique_ptr<float, StbFree> px(stbi_loadf_from_memory(data, int(bytes.size()), &w, &h, &n, 4));
        bytes = std::string();
        if (!px) throw Error(path + ": cannot read image: " + readable_reason(stbi_failure_reason()));
        texels.resize(size_t(w) * size_t(h));
        std::memcpy(static_cast<void*>(texels.data()), px.get(), texels.size() * sizeof(vec4));
    } else {
        const size_t size = bytes.size();
        bytes.append(kPadding, '\0');
        std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(fmemopen(bytes.data(), bytes.size(), "rb"), &std::fclose);
        if (!f) throw Error(path + ": cannot read image: out of memory");
        std::unique_ptr<stbi_uc, StbFree> px(stbi_load_from_file(f.get(), &w, &h, &n, 4));
        if (!px) throw Error(path + ": cannot read image: " + readable_reason(stbi_failure_reason()));
        truncated = uint64_t(std::ftell(f.get())) > size;
        f.reset();
        bytes = std::string();
        // Kept as the file's 8-bit codes (4 bytes a texel), not decoded to floats and recognised again.
        const stbi_uc* q = px.get();
        const bool alpha_from_grey = alpha_only && (n == 1 || n == 3);
        std::vector<uint32_t> codes(size_t(w) * size_t(h));
        for (size_t i = 0; i < codes.size(); ++i)
            codes[i] = uint32_t(q[4 * i]) | uint32_t(q[4 * i + 1]) << 8 | uint32_t(q[4 * i + 2]) << 16 |
                       uint32_t(q[4 * i + (alpha_from_grey ? 0 : 3)]) << 24;
        return finish(Texture(w, h, std::move(codes)));
    }
    return finish(Texture(w, h, std::move(texels)));
}

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

}  // namespace

std::string resolve_texture_path(const std::string& dir, const std::string& name) {
    namespace fs = std::filesystem;
    std::string clean = name;
    std::replace(clean.begin(), clean.end(), '\\', '/');
    std::error_code ec;
    const fs::path direct = fs::path(dir) / clean;
    if (fs::is_regular_file(direct, ec)) return direct.string();
    // Walk the components, matching each case-insensitively.
    fs::path cur = dir.empty() ? fs::path(".") : fs::path(dir);
    for (const fs::path& part : fs::path(clean)) {
        if (part.empty() || part == ".") continue;
        const fs::path exact = cur / part;
        if (fs::exists(exact, ec)) {
            cur = exact;
            continue;
        }
        const std::string want = lower(part.string());
        bool found = false;
        for (fs::directory_iterator it(cur, ec), end; !ec && it != end; it.increment(ec)) {
            if (lower(it->path().filename().string()) == want) {
                cur = it->path();
                found = true;
                break;
            }
        }
        if (!found) return {};
    }
    return fs::is_regular_file(cur, ec) ? cur.string() : std::string();
}

}  // namespace pv
