// core/scene/texture_decode.cpp: untrusted image files into Textures (Texture::load, Texture::decode), and texture
// file names resolved (resolve_texture_path). JPEG through libjpeg-turbo and PNG through libpng (stb_image 2.27's
// decoders of both read and write out of bounds on crafted files); HDR, BMP, TGA, GIF, PSD, PIC, PNM through
// stb_image, guarded (declared size read first, Radiance RLE walked, truncation found); EXR through OpenEXR.
#include "core/scene/texture_decode.h"

#include <png.h>
#include <stb_image.h>
#include <webp/decode.h>

#include <algorithm>
#include <cctype>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

// jpeglib.h needs FILE and size_t declared first.
#include <jerror.h>
#include <jpeglib.h>

#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/image/image_io.h"

namespace pv {
namespace {

enum class Format { Png, Jpeg, Gif, Bmp, Psd, Pic, Pnm, Hdr, Exr, Webp, Other };

bool starts_with(const std::string& s, const char* magic, size_t n) {
    return s.size() >= n && s.compare(0, n, magic, n) == 0;
}

Format sniff(const std::string& b) {
    if (starts_with(b, "\x89PNG\r\n\x1a\n", 8)) return Format::Png;
    // FF D8 (SOI) alone: stb_image takes the bytes after it for a JPEG whatever they are (it skips to the next
    // marker), so every file it would decode as one goes to libjpeg instead, which warns of the bytes it skips.
    if (starts_with(b, "\xff\xd8", 2)) return Format::Jpeg;
    if (starts_with(b, "GIF87a", 6) || starts_with(b, "GIF89a", 6)) return Format::Gif;
    if (starts_with(b, "BM", 2)) return Format::Bmp;
    if (starts_with(b, "8BPS", 4)) return Format::Psd;
    if (starts_with(b, "\x53\x80\xf6\x34", 4)) return Format::Pic;
    if (starts_with(b, "P5", 2) || starts_with(b, "P6", 2)) return Format::Pnm;
    if (starts_with(b, "#?RADIANCE\n", 11) || starts_with(b, "#?RGBE\n", 7)) return Format::Hdr;
    if (starts_with(b, "\x76\x2f\x31\x01", 4)) return Format::Exr;
    if (b.size() >= 12 && starts_with(b, "RIFF", 4) && b.compare(8, 4, "WEBP") == 0) return Format::Webp;
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
        case Format::Webp:
            return 4096.0;  // lossless WebP's colour cache and backward references: a run of pixels in a few bits
        default:
            return 4096.0;
    }
}

// stb_image's failure strings are terse ("bad png sig") and, for some inputs, empty: a readable reason.
std::string readable_reason(const char* stb) {
    const std::string r = stb ? stb : "";
    if (r == "unknown image type")
        return "unknown or unsupported image format; expected PNG, JPEG, WebP, TGA, BMP, PSD, GIF, PNM (P5/P6), HDR or "
               "EXR";
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

// 8-bit RGBA pixels (row 0 at the top) as the Texture of their codes: R, G, B sRGB codes and A linear, kept as the
// file's codes (4 bytes a texel), not decoded to floats and recognised again. `n` is the file's channel count as
// stbi_load reports it: a mask (alpha_only) of a file without alpha (1 or 3 channels) takes its grey level (R).
Texture from_rgba8(const unsigned char* q, int w, int h, int n, bool alpha_only) {
    const bool alpha_from_grey = alpha_only && (n == 1 || n == 3);
    std::vector<uint32_t> codes(size_t(w) * size_t(h));
    for (size_t i = 0; i < codes.size(); ++i)
        codes[i] = uint32_t(q[4 * i]) | uint32_t(q[4 * i + 1]) << 8 | uint32_t(q[4 * i + 2]) << 16 |
                   uint32_t(q[4 * i + (alpha_from_grey ? 0 : 3)]) << 24;
    return Texture(w, h, std::move(codes));
}

// ---------------------------------------------------------------- JPEG (libjpeg-turbo)
// libjpeg's error_exit would exit(); here it formats the message and longjmps back to the setjmp of jpeg_header or
// jpeg_pixels, small functions with no C++ object in their frames (nothing is skipped by the longjmp). Warnings are
// recorded instead of printed: the end of data (libjpeg then decodes the rest as if the data were zeros) becomes
// the truncation warning, the first other one (corrupt data it decoded through) a warning of its own.
struct JpegState {
    jpeg_decompress_struct cinfo;
    jpeg_error_mgr err;
    jpeg_progress_mgr progress;
    std::jmp_buf jump;
    bool created = false;
    bool ended_early = false;
    char message[JMSG_LENGTH_MAX] = "";
    char warning[JMSG_LENGTH_MAX] = "";
};

// A progressive JPEG may have any number of scans, each a pass over the whole image: libjpeg-turbo's advice
// (libjpeg.txt, djpeg -maxscans) is to bound them. Real encoders write at most a few dozen.
constexpr int kMaxJpegScans = 1000;

void jpeg_fail(j_common_ptr c) {
    auto* s = static_cast<JpegState*>(c->client_data);
    c->err->format_message(c, s->message);
    std::longjmp(s->jump, 1);
}

void jpeg_note(j_common_ptr c, int level) {
    if (level >= 0) return;  // trace messages
    auto* s = static_cast<JpegState*>(c->client_data);
    if (c->err->msg_code == JWRN_JPEG_EOF)
        s->ended_early = true;
    else if (!s->warning[0])
        c->err->format_message(c, s->warning);
    ++c->err->num_warnings;
}

void jpeg_scans(j_common_ptr c) {
    auto* s = static_cast<JpegState*>(c->client_data);
    if (s->cinfo.input_scan_number > kMaxJpegScans) {
        std::snprintf(s->message, sizeof s->message, "more than %d progressive scans", kMaxJpegScans);
        std::longjmp(s->jump, 1);
    }
}

bool jpeg_header(JpegState& s, const unsigned char* data, size_t size) {
    s.cinfo.err = jpeg_std_error(&s.err);
    s.err.error_exit = jpeg_fail;
    s.err.emit_message = jpeg_note;
    s.cinfo.client_data = &s;
    if (setjmp(s.jump)) return false;
    jpeg_create_decompress(&s.cinfo);
    s.created = true;
    s.progress.progress_monitor = jpeg_scans;
    s.cinfo.progress = &s.progress;
    jpeg_mem_src(&s.cinfo, data, static_cast<unsigned long>(size));
    jpeg_read_header(&s.cinfo, TRUE);
    return true;
}

// Decodes into `out`, output_width x output_height x 4 bytes as jpeg_calc_output_dimensions found them.
bool jpeg_pixels(JpegState& s, unsigned char* out, JDIMENSION w, JDIMENSION h) {
    if (setjmp(s.jump)) return false;
    jpeg_start_decompress(&s.cinfo);
    if (s.cinfo.output_width != w || s.cinfo.output_height != h || s.cinfo.output_components != 4) {
        std::snprintf(s.message, sizeof s.message, "unexpected output size");
        return false;
    }
    // Every scanline read is the whole image: jpeg_finish_decompress would only look for the EOI marker.
    while (s.cinfo.output_scanline < h) {
        JSAMPROW row = out + size_t(s.cinfo.output_scanline) * w * 4;
        jpeg_read_scanlines(&s.cinfo, &row, 1);
    }
    return true;
}

struct JpegDestroy {
    JpegState& s;
    ~JpegDestroy() {
        if (s.created) jpeg_destroy_decompress(&s.cinfo);
    }
};

// x * y / 255 rounded, as stb_image's stbi__blinn_8x8.
unsigned char blinn_8x8(unsigned x, unsigned y) {
    const unsigned t = x * y + 128;
    return static_cast<unsigned char>((t + (t >> 8)) >> 8);
}

// Grey, YCbCr and RGB JPEGs as libjpeg-turbo's RGBA; CMYK and YCCK (Adobe) ones as libjpeg's CMYK, which is stored
// inverted (255 = no ink), times K as stb_image converts them: R = C * K / 255.
Texture decode_jpeg(const std::string& bytes, const std::string& path, bool alpha_only,
                    std::vector<std::string>& warnings) {
    auto s = std::make_unique<JpegState>();
    JpegDestroy destroy{*s};
    auto fail = [&](const char* what) {
        return Error(path + ": cannot read image: corrupt or unsupported JPEG data (libjpeg: " + what + ")");
    };
    if (!jpeg_header(*s, reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size())) throw fail(s->message);
    jpeg_decompress_struct& c = s->cinfo;
    const JDIMENSION w = c.image_width, h = c.image_height;
    check_declared_size(path, w, h, bytes.size(), pixels_per_byte(Format::Jpeg));
    const bool cmyk = c.jpeg_color_space == JCS_CMYK || c.jpeg_color_space == JCS_YCCK;
    c.out_color_space = cmyk ? JCS_CMYK : JCS_EXT_RGBA;
    c.dct_method = JDCT_ISLOW;  // the default: the accurate integer IDCT, and fancy upsampling
    // libjpeg's own allocations: a progressive JPEG's coefficients (2 bytes each, 64 a block of 8x8 pixels per
    // component at full resolution, blocks padded to 32-pixel MCUs) and 64 MiB for the rest. Past it libjpeg fails
    // (it has no backing store) rather than allocating what a crafted header asks for.
    const uint64_t padded = uint64_t(w + 31) / 32 * 32 * (uint64_t(h + 31) / 32 * 32);
    const uint64_t budget = padded * 2 * uint64_t(std::max(c.num_components, 1)) + (uint64_t(64) << 20);
    c.mem->max_memory_to_use = long(std::min<uint64_t>(budget, uint64_t(std::numeric_limits<long>::max())));
    std::vector<unsigned char> px(size_t(w) * size_t(h) * 4);
    if (!jpeg_pixels(*s, px.data(), w, h)) {
        if (s->err.msg_code == JERR_NO_BACKING_STORE)
            throw Error(path + ": cannot read image: the JPEG needs more than " + std::to_string(budget >> 20) +
                        " MiB to decode");
        throw fail(s->message);
    }
    if (cmyk)
        for (size_t i = 0; i < px.size(); i += 4) {
            const unsigned k = px[i + 3];
            px[i] = blinn_8x8(px[i], k);
            px[i + 1] = blinn_8x8(px[i + 1], k);
            px[i + 2] = blinn_8x8(px[i + 2], k);
            px[i + 3] = 255;
        }
    // At the end of the data libjpeg inserts an end-of-image marker, warns, and warns again of the marker it then
    // meets inside the entropy-coded data: one warning, the truncation's.
    if (s->ended_early)
        warnings.push_back("the image data ends early (truncated file?); libjpeg fills in what is missing (grey)");
    else if (s->warning[0])
        warnings.push_back(std::string("corrupt JPEG data, decoded as far as possible (libjpeg: ") + s->warning + ")");
    return from_rgba8(px.data(), int(w), int(h), c.num_components >= 3 ? 3 : 1, alpha_only);
}

// ---------------------------------------------------------------- PNG (libpng)
// libpng's errors, like libjpeg's, longjmp back to png_header or png_pixels (no C++ object in their frames); its
// warnings (benign errors, ancillary chunks with bad CRCs) are ignored, as stb_image ignores those chunks.
struct PngState {
    png_structp png = nullptr;
    png_infop info = nullptr;
    const unsigned char* data = nullptr;
    size_t size = 0, pos = 0;
    std::jmp_buf jump;
    bool ended_early = false;
    bool reading_rows = false;
    char message[256] = "";
};

void png_fail(png_structp png, png_const_charp msg) {
    auto* s = static_cast<PngState*>(png_get_error_ptr(png));
    std::snprintf(s->message, sizeof s->message, "%s", msg ? msg : "");
    std::longjmp(s->jump, 1);
}

void png_ignore(png_structp, png_const_charp) {}

void png_from_memory(png_structp png, png_bytep out, size_t n) {
    auto* s = static_cast<PngState*>(png_get_io_ptr(png));
    if (n > s->size - s->pos) {
        s->ended_early = true;
        png_error(png, "the data ends early");
    }
    std::memcpy(out, s->data + s->pos, n);
    s->pos += n;
}

bool png_header(PngState& s) {
    if (setjmp(s.jump)) return false;
    s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &s, png_fail, png_ignore);
    if (s.png) s.info = png_create_info_struct(s.png);
    if (!s.info) {
        std::snprintf(s.message, sizeof s.message, "out of memory");
        return false;
    }
    png_set_read_fn(s.png, &s, png_from_memory);
    // Image data read 1 KiB at a time (libpng's default is 8 KiB): of a truncated file, the rows before the last
    // KiB are decoded.
    png_set_compression_buffer_size(s.png, 1024);
    png_read_info(s.png, s.info);
    return true;
}

// As stb_image decodes a PNG into 8-bit RGBA: palette to RGB, grey below 8 bits scaled up, a tRNS chunk to alpha,
// 16 bits to their high byte, grey to RGB, opaque alpha added; no gamma or ICC conversion. Into `out`, w x h x 4
// bytes; rows the data does not reach keep what `out` held.
bool png_pixels(PngState& s, unsigned char* out, png_uint_32 w, png_uint_32 h) {
    if (setjmp(s.jump)) return false;
    png_set_expand(s.png);
    png_set_strip_16(s.png);
    png_set_gray_to_rgb(s.png);
    png_set_add_alpha(s.png, 0xff, PNG_FILLER_AFTER);
    const int passes = png_set_interlace_handling(s.png);
    png_read_update_info(s.png, s.info);
    if (png_get_rowbytes(s.png, s.info) != size_t(w) * 4) png_error(s.png, "unexpected row size");
    s.reading_rows = true;
    for (int p = 0; p < passes; ++p)
        for (png_uint_32 y = 0; y < h; ++y) png_read_row(s.png, out + size_t(y) * w * 4, nullptr);
    return true;
}

struct PngDestroy {
    PngState& s;
    ~PngDestroy() {
        if (s.png) png_destroy_read_struct(&s.png, s.info ? &s.info : nullptr, nullptr);
    }
};

Texture decode_png(const std::string& bytes, const std::string& path, bool alpha_only,
                   std::vector<std::string>& warnings) {
    auto s = std::make_unique<PngState>();
    PngDestroy destroy{*s};
    s->data = reinterpret_cast<const unsigned char*>(bytes.data());
    s->size = bytes.size();
    auto fail = [&] {
        return Error(path + ": cannot read image: " +
                     (s->ended_early ? "the PNG data ends before its image data"
                                     : "corrupt or unsupported PNG data (libpng: " + std::string(s->message) + ")"));
    };
    if (!png_header(*s)) throw fail();
    const png_uint_32 w = png_get_image_width(s->png, s->info), h = png_get_image_height(s->png, s->info);
    check_declared_size(path, w, h, bytes.size(), pixels_per_byte(Format::Png));
    // The channel count stbi_load reports: a palette's entries (RGB, or RGBA with a tRNS chunk), else the file's
    // channels, one more for a grey or RGB image with a tRNS chunk (its transparent colour).
    const bool trns = png_get_valid(s->png, s->info, PNG_INFO_tRNS) != 0;
    const int n = png_get_color_type(s->png, s->info) == PNG_COLOR_TYPE_PALETTE
                      ? (trns ? 4 : 3)
                      : int(png_get_channels(s->png, s->info)) + (trns ? 1 : 0);
    // Pixels the data does not reach are opaque black.
    std::vector<uint32_t> px(size_t(w) * size_t(h), 0xff000000u);
    auto* out = reinterpret_cast<unsigned char*>(px.data());
    if (!png_pixels(*s, out, w, h)) {
        if (!(s->ended_early && s->reading_rows)) throw fail();
        warnings.push_back("the image data ends early (truncated file?); missing pixels are black");
    }
    return from_rgba8(out, int(w), int(h), n, alpha_only);
}

}  // namespace

std::string read_image_file(const std::string& path, const char* what) {
    const std::string head = read_regular_file_prefix(path, size_t(1) << 16, what);
    const Format format = sniff(head);
    const uint64_t size = regular_file_size(path, what);
    constexpr uint64_t kSlack = uint64_t(64) << 20;
    uint64_t need = image_limits().max_pixels * 16 + kSlack;  // the largest file the budget can need
    int w = 0, h = 0, n = 0;
    if (format != Format::Exr &&
        stbi_info_from_memory(reinterpret_cast<const stbi_uc*>(head.data()), int(head.size()), &w, &h, &n)) {
        check_declared_size(path, w, h, size, pixels_per_byte(format));
        need = std::min(need, uint64_t(w) * uint64_t(h) * 16 + kSlack);
        if (size > need)
            throw Error(path + ": the file is " + std::to_string(size) + " bytes; a " + std::to_string(w) + "x" +
                        std::to_string(h) + " image needs at most " + std::to_string(need));
    } else if (format == Format::Webp) {  // stb_image does not read WebP: its header, through libwebp
        WebPBitstreamFeatures features;
        if (WebPGetFeatures(reinterpret_cast<const uint8_t*>(head.data()), head.size(), &features) != VP8_STATUS_OK)
            throw Error(path + ": cannot read image: corrupt or unsupported WebP header");
        check_declared_size(path, features.width, features.height, size, pixels_per_byte(format));
        // A RIFF file states its own length: nothing past it is read.
        need = std::min(need, uint64_t(uint8_t(head[4])) | uint64_t(uint8_t(head[5])) << 8 |
                                  uint64_t(uint8_t(head[6])) << 16 | uint64_t(uint8_t(head[7])) << 24);
        need += 8;
    } else if (format == Format::Other) {
        throw Error(path + ": cannot read image: " + readable_reason(stbi_failure_reason()));
    }
    return read_regular_file(path, need, what);
}

bool image_header_size(const unsigned char* bytes, size_t size, int& width, int& height) {
    int n = 0;
    return size <= size_t(std::numeric_limits<int>::max()) && size >= 4 &&
           std::memcmp(bytes, "\x76\x2f\x31\x01", 4) != 0 &&
           stbi_info_from_memory(bytes, int(size), &width, &height, &n) != 0;
}

Texture Texture::load(const std::string& path, bool alpha_only, std::vector<std::string>* warnings) {
    const char* what = "an image (PNG, JPEG, WebP, TGA, BMP, PSD, GIF, PNM, HDR or EXR)";
    // An EXR is read by OpenEXR from the file, not copied into memory first.
    if (sniff(read_regular_file_prefix(path, 4, what)) == Format::Exr) {
        int w = 0, h = 0;
        std::vector<vec4> texels = read_exr_rgba(path, w, h);
        return from_exr_texels(std::move(texels), w, h);
    }
    return decode(read_image_file(path, what), path, alpha_only, warnings);
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
    if (format == Format::Webp) {
        // libwebp reads the dimensions from the header; the budget is checked before anything is decoded.
        const auto* data = reinterpret_cast<const uint8_t*>(bytes.data());
        WebPBitstreamFeatures features;
        if (WebPGetFeatures(data, bytes.size(), &features) != VP8_STATUS_OK)
            throw Error(path + ": cannot read image: corrupt or unsupported WebP header");
        check_declared_size(path, features.width, features.height, bytes.size(), pixels_per_byte(format));
        std::unique_ptr<uint8_t, void (*)(void*)> px(WebPDecodeRGBA(data, bytes.size(), &w, &h), &WebPFree);
        if (!px) throw Error(path + ": cannot read image: corrupt or truncated WebP data");
        bytes = std::string();
        return from_rgba8(px.get(), w, h, features.has_alpha ? 4 : 3, alpha_only);
    }
    if (format == Format::Jpeg || format == Format::Png) {
        std::vector<std::string> found;
        Texture t = format == Format::Jpeg ? decode_jpeg(bytes, path, alpha_only, found)
                                           : decode_png(bytes, path, alpha_only, found);
        for (const std::string& f : found) warn(f);
        return t;
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
        return finish(from_rgba8(px.get(), w, h, n, alpha_only));
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
