// core/scene/texture.cpp: stb_image loading, sRGB decoding and bilinear lookup.
// stb_image 2.27 (Debian 12) has no limits of its own and loops forever on some Radiance RLE data; it is guarded
// here rather than replaced (OpenImageIO 2.4 would be the alternative): the faults are narrow and known, the guards
// (declared size read first, the RLE walk, truncation found from stb's read position) are small and fuzzed
// (tests/fuzz/fuzz_image.cpp), and OpenImageIO would add a large dependency tree to every build and CI run.
#include "core/scene/texture.h"

#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/base/huge_pages.h"
#include "core/image/image_io.h"

namespace pv {
namespace {

// sRGB EOTF (IEC 61966-2-1).
float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// The sRGB decoding of the 256 8-bit codes, as Texture::load applies it.
const float* srgb_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_to_linear(float(i) / 255.f);
        return t;
    }();
    return table.data();
}

bool same_bits(float a, float b) {
    uint32_t x, y;
    std::memcpy(&x, &a, 4);
    std::memcpy(&y, &b, 4);
    return x == y;
}

// The 8-bit sRGB code whose decoding is exactly v, or -1. The table is increasing: a bucket of v's value gives the
// first candidate code, and a short walk up finds the first code not below v (a binary search over the 256 codes
// per channel doubled Sponza's load time).
int srgb_code(float v) {
    constexpr int kBuckets = 1024;
    static const std::array<uint8_t, kBuckets + 1> first = [] {
        std::array<uint8_t, kBuckets + 1> f{};
        const float* table = srgb_table();
        int c = 0;
        for (int b = 0; b <= kBuckets; ++b) {
            while (c < 255 && table[c] < float(b) / float(kBuckets)) ++c;
            f[size_t(b)] = uint8_t(c > 0 ? c - 1 : 0);  // one below: bucket edges are rounded
        }
        return f;
    }();
    if (!(v >= 0.f && v <= 1.f)) return -1;
    const float* table = srgb_table();
    int c = first[size_t(v * float(kBuckets))];
    while (c < 255 && table[c] < v) ++c;
    return same_bits(table[c], v) ? c : -1;
}

// The 8-bit code c with c / 255 exactly a (alpha is stored linear), or -1.
int alpha_code(float a) {
    if (!(a >= 0.f && a <= 1.f)) return -1;
    const int c = int(std::lround(a * 255.f));
    return same_bits(float(c) / 255.f, a) ? c : -1;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

}  // namespace

float srgb_code_to_linear(int c) { return srgb_table()[std::clamp(c, 0, 255)]; }

namespace {

// Storage of `data`'s elements that owns them: null when empty.
template <typename T>
std::shared_ptr<const T> own(std::vector<T> data) {
    if (data.empty()) return nullptr;
    auto v = std::make_shared<std::vector<T>>(std::move(data));
    return std::shared_ptr<const T>(v, v->data());
}

}  // namespace

Texture::Texture(int width, int height, std::vector<vec4> texels)
    : m_width(width), m_height(height), m_wrap_x(wrap_magic(width)), m_wrap_y(wrap_magic(height)) {
    for (vec4& t : texels) {
        // A texel is finite and in [0, kMaxTexel]: bilinear weights of texels near FLT_MAX can round the lookup up
        // to Inf (found by fuzz_image on an EXR holding uninitialised-looking huge values), and an environment
        // map's importance sums stay finite.
        t = std::isfinite(t.x + t.y + t.z + t.w) ? glm::clamp(t, vec4(0.f), vec4(kMaxTexel)) : vec4(0.f, 0.f, 0.f, 1.f);
        m_has_alpha = m_has_alpha || t.w < 1.f;
    }
    // Keep 8-bit codes instead when every texel is one exactly (bit for bit, so lookups return the same values).
    std::vector<uint32_t> codes(texels.size());
    for (size_t i = 0; i < texels.size(); ++i) {
        const vec4& t = texels[i];
        const int r = srgb_code(t.x), g = srgb_code(t.y), b = srgb_code(t.z), a = alpha_code(t.w);
        if ((r | g | b | a) < 0) {
            m_count = texels.size();
            m_texels = own(std::move(texels));
            return;
        }
        codes[i] = uint32_t(r) | uint32_t(g) << 8 | uint32_t(b) << 16 | uint32_t(a) << 24;
    }
    texels = std::vector<vec4>();
    tile(codes);
}

Texture::Texture(int width, int height, std::vector<uint32_t> codes)
    : m_width(width), m_height(height), m_wrap_x(wrap_magic(width)), m_wrap_y(wrap_magic(height)) {
    for (const uint32_t c : codes)
        if ((c >> 24) < 255u) {
            m_has_alpha = true;
            break;
        }
    tile(codes);
}

void Texture::tile(const std::vector<uint32_t>& codes) {
    if (codes.empty()) return;
    const size_t w = size_t(m_width), h = size_t(m_height);
    m_blocks_per_row = (w + 3) / 4;
    std::vector<CodeBlock> blocks(m_blocks_per_row * ((h + 3) / 4), CodeBlock{});
    for (size_t y = 0; y < h; ++y)
        for (size_t x = 0; x < w; ++x) {
            const size_t i = tiled_index(x, y, m_blocks_per_row);
            blocks[i >> 4].code[i & 15] = codes[y * w + x];
        }
    m_count = blocks.size();
    m_blocks = own(std::move(blocks));
}

void pack_texels(std::vector<Texture>& textures) {
    // Each texture's storage at a 64-byte boundary (a code block is one cache line).
    auto padded = [](size_t bytes) { return (bytes + 63) / 64 * 64; };
    size_t total = 0;
    for (const Texture& t : textures) total += padded(t.bytes());
    if (total == 0) return;
    const std::shared_ptr<std::byte> region = allocate_region(total);
    size_t offset = 0;
    for (Texture& t : textures) {
        if (t.empty()) continue;
        std::byte* at = region.get() + offset;
        std::memcpy(at, t.storage(), t.bytes());
        offset += padded(t.bytes());
        if (t.m_blocks)
            t.m_blocks = std::shared_ptr<const Texture::CodeBlock>(region, reinterpret_cast<Texture::CodeBlock*>(at));
        else
            t.m_texels = std::shared_ptr<const vec4>(region, reinterpret_cast<vec4*>(at));
    }
    // The textures' own storage, as large as the region, was just freed: glibc keeps it mapped otherwise.
    return_freed_heap_memory();
}

std::vector<vec4> Texture::texels() const {
    if (!m_blocks) return std::vector<vec4>(m_texels.get(), m_texels.get() + m_count);
    const size_t w = size_t(m_width), h = size_t(m_height);
    std::vector<vec4> out(w * h);
    for (size_t y = 0; y < h; ++y)
        for (size_t x = 0; x < w; ++x) out[y * w + x] = texel(tiled_index(x, y, m_blocks_per_row));
    return out;
}

// Texel i of the storage: row-major floats, or the tiled codes decoded.
inline vec4 Texture::texel(size_t i) const {
    if (!m_blocks) return m_texels.get()[i];
    const float* table = srgb_table();
    const uint32_t c = m_blocks.get()[i >> 4].code[i & 15];
    return vec4(table[c & 0xffu], table[(c >> 8) & 0xffu], table[(c >> 16) & 0xffu], float(c >> 24) / 255.f);
}

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

// The texel indices of a bilinear pair along one axis, f and f + 1 for f the floor of the (finite) texel coordinate,
// wrapped by `mode` into [0, n): the textures that do not repeat on both axes (glTF samplers) come here.
void wrapped_pair(float f, int n, TextureWrap mode, uint64_t magic, size_t& i0, size_t& i1) {
    switch (mode) {
        case TextureWrap::Repeat: {
            const auto i = static_cast<long long>(std::fabs(f) < 0x1p62f ? f : std::fmod(f, float(n)));
            i0 = wrap_texel_index(i, n, magic);
            i1 = i0 + 1 == size_t(n) ? 0 : i0 + 1;
            return;
        }
        case TextureWrap::ClampToEdge: {
            // Clamped as a float first: any finite f, however large, becomes an index in [-1, n].
            const auto i = static_cast<long long>(std::clamp(f, -1.f, float(n)));
            i0 = size_t(std::clamp<long long>(i, 0, n - 1));
            i1 = size_t(std::clamp<long long>(i + 1, 0, n - 1));
            return;
        }
        case TextureWrap::MirroredRepeat: {
            // Period 2n: beyond 2^62 f is a whole number, and fmod in double reduces it exactly (2n is exact there).
            const long long p = 2ll * n;
            const auto i = static_cast<long long>(std::fabs(f) < 0x1p62f ? double(f) : std::fmod(double(f), double(p)));
            long long k = i % p;
            if (k < 0) k += p;
            const long long k1 = k + 1 == p ? 0 : k + 1;
            i0 = size_t(k < n ? k : p - 1 - k);
            i1 = size_t(k1 < n ? k1 : p - 1 - k1);
            return;
        }
    }
    i0 = i1 = 0;
}

}  // namespace

// The four texels of a bilinear lookup at uv and their weights; not valid for a non-finite uv.
inline TexelFootprint Texture::footprint(vec2 uv) const {
    TexelFootprint fp;
    // Texel centres at (i + 0.5) / width; v flipped because image row 0 is the top.
    const float x = uv.x * float(m_width) - 0.5f;
    const float y = (1.f - uv.y) * float(m_height) - 0.5f;
    if (!std::isfinite(x) || !std::isfinite(y)) return fp;
    fp.valid = true;
    const float fx = std::floor(x), fy = std::floor(y);
    fp.tx = x - fx;
    fp.ty = y - fy;
    // A finite uv can be beyond the range of long long (a file's uvs or transform): such a float is a whole number,
    // and fmod reduces it exactly to the same residue, so the wrap is still the modulo.
    const auto whole = [](float f, int n) {
        return static_cast<long long>(std::fabs(f) < 0x1p62f ? f : std::fmod(f, float(n)));
    };
    size_t x0, x1, y0, y1;
    if (m_repeat) [[likely]] {  // one test per lookup, the same way for every lookup of this texture
        const long long ix = whole(fx, m_width), iy = whole(fy, m_height);
        x0 = wrap_texel_index(ix, m_width, m_wrap_x), x1 = x0 + 1 == size_t(m_width) ? 0 : x0 + 1;
        y0 = wrap_texel_index(iy, m_height, m_wrap_y), y1 = y0 + 1 == size_t(m_height) ? 0 : y0 + 1;
    } else {
        wrapped_pair(fx, m_width, m_wrap_s, m_wrap_x, x0, x1);
        wrapped_pair(fy, m_height, m_wrap_t, m_wrap_y, y0, y1);
    }
    if (m_blocks) {
        const size_t b = m_blocks_per_row;
        fp.index[0] = tiled_index(x0, y0, b);
        fp.index[1] = tiled_index(x1, y0, b);
        fp.index[2] = tiled_index(x0, y1, b);
        fp.index[3] = tiled_index(x1, y1, b);
        return fp;
    }
    const size_t w = size_t(m_width);
    fp.index[0] = y0 * w + x0;
    fp.index[1] = y0 * w + x1;
    fp.index[2] = y1 * w + x0;
    fp.index[3] = y1 * w + x1;
    return fp;
}

vec4 Texture::lookup(vec2 uv) const {
    if (empty()) return vec4(1.f);
    return lookup(footprint(uv));
}

vec4 Texture::lookup(const TexelFootprint& fp) const {
    if (empty()) return vec4(1.f);
    if (!fp.valid) return texel(0);
    const size_t* i = fp.index;
    const float tx = fp.tx, ty = fp.ty;
    return (1.f - ty) * ((1.f - tx) * texel(i[0]) + tx * texel(i[1])) +
           ty * ((1.f - tx) * texel(i[2]) + tx * texel(i[3]));
}

TexelFootprint Texture::prefetch(vec2 uv) const {
    if (empty()) return {};
    const TexelFootprint fp = footprint(uv);
    if (!fp.valid) return fp;
    for (const size_t k : fp.index) {
        if (m_blocks)
            __builtin_prefetch(m_blocks.get() + (k >> 4));
        else
            __builtin_prefetch(m_texels.get() + k);
    }
    return fp;
}

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
