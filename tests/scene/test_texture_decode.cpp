// tests/scene/test_texture_decode.cpp: JPEG (libjpeg-turbo) and PNG (libpng) decoding in Texture::decode. Files are
// written here (libpng's and libjpeg's encoders, stb_image_write) and decoded both by Texture::decode and by
// stb_image, which decoded them before: PNGs give the same texels bit for bit, JPEGs the same within the rounding of
// two conforming decoders. Truncated and corrupt files warn or fail naming the file; a declared size over the budget
// is refused before the pixels are allocated.
// Test kinds: unit
#include <gtest/gtest.h>
#include <png.h>
#include <stb_image.h>
#include <stb_image_write.h>
#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

// jpeglib.h needs FILE and size_t declared first.
#include <jpeglib.h>

#include "core/base/error.h"
#include "core/image/image_io.h"
#include "core/scene/texture.h"
#include "support/child.h"

namespace pv {
namespace {

bool contains(const std::string& s, const std::string& needle) { return s.find(needle) != std::string::npos; }

// Deterministic bytes: smooth gradients plus noise (JPEG-friendly, every code reached).
std::vector<unsigned char> test_pixels(int w, int h, int channels, int bytes_per_sample, uint32_t seed) {
    std::vector<unsigned char> px(size_t(w) * h * channels * bytes_per_sample);
    uint32_t x = seed;
    for (int y = 0; y < h; ++y)
        for (int i = 0; i < w; ++i)
            for (int c = 0; c < channels; ++c)
                for (int b = 0; b < bytes_per_sample; ++b) {
                    x = x * 1664525u + 1013904223u;
                    const int smooth = (i * 255 / std::max(w - 1, 1) + y * 97 / std::max(h - 1, 1) + c * 60) % 256;
                    px[((size_t(y) * w + i) * channels + c) * bytes_per_sample + b] =
                        static_cast<unsigned char>(b == 0 ? (smooth + int(x >> 29)) % 256 : int(x >> 24));
                }
    return px;
}

// ---------------------------------------------------------------- writers

struct PngSpec {
    int color_type = PNG_COLOR_TYPE_RGB;
    int bit_depth = 8;
    bool interlaced = false;
    bool trns = false;   // a tRNS chunk (palette: per-entry alpha; grey/RGB: one transparent value)
    bool gamma = false;  // a gAMA chunk of 1.0 (stb_image ignores it, and so must we)
};

void png_append(png_structp png, png_bytep data, size_t n) {
    static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), n);
}
void png_flush_nothing(png_structp) {}

int png_channels(int color_type) {
    switch (color_type) {
        case PNG_COLOR_TYPE_GRAY:
        case PNG_COLOR_TYPE_PALETTE:
            return 1;
        case PNG_COLOR_TYPE_GRAY_ALPHA:
            return 2;
        case PNG_COLOR_TYPE_RGB:
            return 3;
        default:
            return 4;
    }
}

// A w x h PNG of `spec` with test_pixels samples (masked to the bit depth, packed as PNG packs them).
std::string write_png_bytes(int w, int h, const PngSpec& spec, uint32_t seed = 7) {
    std::string out;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) std::abort();  // only valid parameters are written
    png_set_write_fn(png, &out, png_append, png_flush_nothing);
    png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), spec.bit_depth, spec.color_type,
                 spec.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    const int entries = 1 << std::min(spec.bit_depth, 8);
    if (spec.color_type == PNG_COLOR_TYPE_PALETTE) {
        std::vector<png_color> pal(static_cast<size_t>(entries));
        for (int i = 0; i < entries; ++i)
            pal[size_t(i)] = png_color{png_byte(i * 37), png_byte(255 - i * 11), png_byte(i * i)};
        png_set_PLTE(png, info, pal.data(), entries);
    }
    if (spec.trns) {
        if (spec.color_type == PNG_COLOR_TYPE_PALETTE) {
            std::vector<png_byte> alpha(static_cast<size_t>(entries));
            for (int i = 0; i < entries; ++i) alpha[size_t(i)] = png_byte(255 - i * 13);
            png_set_tRNS(png, info, alpha.data(), entries, nullptr);
        } else {
            png_color_16 key{};
            const int mask = (1 << spec.bit_depth) - 1;
            key.gray = png_uint_16(3 & mask);
            key.red = 0, key.green = 0, key.blue = 0;
            png_set_tRNS(png, info, nullptr, 0, &key);
        }
    }
    if (spec.gamma) png_set_gAMA(png, info, 1.0);
    png_write_info(png, info);
    const int channels = png_channels(spec.color_type);
    const int bytes = spec.bit_depth == 16 ? 2 : 1;
    std::vector<unsigned char> px = test_pixels(w, h, channels, bytes, seed);
    if (spec.bit_depth < 8) {  // samples of bit_depth bits, packed from the high bits of each byte
        const int mask = (1 << spec.bit_depth) - 1, per_byte = 8 / spec.bit_depth;
        const size_t row_bytes = (size_t(w) * spec.bit_depth + 7) / 8;
        std::vector<unsigned char> packed(row_bytes * h, 0);
        for (int y = 0; y < h; ++y)
            for (int i = 0; i < w; ++i) {
                const int v = px[size_t(y) * w + i] & mask;
                packed[size_t(y) * row_bytes + i / per_byte] |=
                    static_cast<unsigned char>(v << (8 - spec.bit_depth * (i % per_byte + 1)));
            }
        px = std::move(packed);
    } else if (spec.color_type == PNG_COLOR_TYPE_PALETTE) {
        for (unsigned char& v : px) v = static_cast<unsigned char>(v % entries);
    }
    if (spec.trns && spec.color_type != PNG_COLOR_TYPE_PALETTE && bytes == 1 && spec.bit_depth == 8)
        for (size_t i = 0; i < px.size(); i += 7) px[i] = 3;  // some pixels equal to the grey key
    const size_t stride = px.size() / size_t(h);
    std::vector<png_bytep> rows(static_cast<size_t>(h));
    for (int y = 0; y < h; ++y) rows[size_t(y)] = px.data() + size_t(y) * stride;
    png_write_image(png, rows.data());
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return out;
}

struct JpegSpec {
    J_COLOR_SPACE in = JCS_RGB;  // JCS_GRAYSCALE, JCS_RGB or JCS_CMYK (written as Adobe YCCK)
    bool progressive = false;
    bool subsampled = true;  // 4:2:0 chroma
    int quality = 90;
};

std::string write_jpeg_bytes(int w, int h, const JpegSpec& spec, uint32_t seed = 11) {
    jpeg_compress_struct c;
    jpeg_error_mgr err;
    c.err = jpeg_std_error(&err);  // only valid parameters: the default error_exit is never reached
    jpeg_create_compress(&c);
    unsigned char* buf = nullptr;
    unsigned long size = 0;
    jpeg_mem_dest(&c, &buf, &size);
    c.image_width = JDIMENSION(w);
    c.image_height = JDIMENSION(h);
    c.input_components = spec.in == JCS_GRAYSCALE ? 1 : spec.in == JCS_CMYK ? 4 : 3;
    c.in_color_space = spec.in;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, spec.quality, TRUE);
    if (!spec.subsampled)
        for (int i = 0; i < c.num_components; ++i) c.comp_info[i].h_samp_factor = c.comp_info[i].v_samp_factor = 1;
    if (spec.progressive) jpeg_simple_progression(&c);
    jpeg_start_compress(&c, TRUE);
    std::vector<unsigned char> px = test_pixels(w, h, c.input_components, 1, seed);
    while (c.next_scanline < c.image_height) {
        JSAMPROW row = px.data() + size_t(c.next_scanline) * w * c.input_components;
        jpeg_write_scanlines(&c, &row, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    std::string out(reinterpret_cast<const char*>(buf), size);
    std::free(buf);
    return out;
}

// ---------------------------------------------------------------- references

// The texture stb_image 2.27 made of these bytes (the code this replaced: stbi_load's channel count, RGBA codes).
Texture stb_texture(const std::string& bytes, bool alpha_only) {
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    int w = 0, h = 0, n = 0;  // n: the channels stbi_load reports
    stbi_uc* px = stbi_load_from_memory(data, int(bytes.size()), &w, &h, &n, 4);
    EXPECT_NE(px, nullptr) << stbi_failure_reason();
    if (!px) return Texture();
    const bool alpha_from_grey = alpha_only && (n == 1 || n == 3);
    std::vector<uint32_t> codes(size_t(w) * size_t(h));
    for (size_t i = 0; i < codes.size(); ++i)
        codes[i] = uint32_t(px[4 * i]) | uint32_t(px[4 * i + 1]) << 8 | uint32_t(px[4 * i + 2]) << 16 |
                   uint32_t(px[4 * i + (alpha_from_grey ? 0 : 3)]) << 24;
    stbi_image_free(px);
    return Texture(w, h, std::move(codes));
}

// `bytes` decoded by Texture::decode (as `name`) into `ours` and by stb_image, the decoder it replaced, into `stb`;
// both must be w x h, and decode must not warn.
void decode_both(const std::string& bytes, const char* name, bool alpha_only, int w, int h, const std::string& what,
                 Texture& ours, Texture& stb) {
    std::vector<std::string> warnings;
    ours = Texture::decode(bytes, name, alpha_only, &warnings);
    stb = stb_texture(bytes, alpha_only);
    ASSERT_EQ(ours.width(), w) << what;
    ASSERT_EQ(ours.height(), h) << what;
    EXPECT_TRUE(warnings.empty()) << what << ": " << warnings[0];
}

// The 8-bit sRGB code of a linear texel value (its inverse, srgb_code_to_linear, is exact on codes).
int code_of(float linear) {
    int best = 0;
    for (int c = 1; c < 256; ++c)
        if (std::abs(srgb_code_to_linear(c) - linear) < std::abs(srgb_code_to_linear(best) - linear)) best = c;
    return best;
}

// ---------------------------------------------------------------- valid files

TEST(TextureDecode, PngOfEveryColourTypeAndDepthDecodesAsStbImageDid) {
    const std::vector<std::pair<PngSpec, const char*>> specs = {
        {{PNG_COLOR_TYPE_GRAY, 1}, "grey 1"},
        {{PNG_COLOR_TYPE_GRAY, 2}, "grey 2"},
        {{PNG_COLOR_TYPE_GRAY, 4}, "grey 4"},
        {{PNG_COLOR_TYPE_GRAY, 8}, "grey 8"},
        {{PNG_COLOR_TYPE_GRAY, 16}, "grey 16"},
        {{PNG_COLOR_TYPE_GRAY, 8, false, true}, "grey 8 tRNS"},
        {{PNG_COLOR_TYPE_GRAY, 16, false, false, true}, "grey 16 gAMA 1.0"},
        {{PNG_COLOR_TYPE_GRAY_ALPHA, 8}, "grey+alpha 8"},
        {{PNG_COLOR_TYPE_GRAY_ALPHA, 16}, "grey+alpha 16"},
        {{PNG_COLOR_TYPE_RGB, 8}, "RGB 8"},
        {{PNG_COLOR_TYPE_RGB, 8, true}, "RGB 8 interlaced"},
        {{PNG_COLOR_TYPE_RGB, 8, false, true}, "RGB 8 tRNS"},
        {{PNG_COLOR_TYPE_RGB, 8, false, false, true}, "RGB 8 gAMA 1.0"},
        {{PNG_COLOR_TYPE_RGB, 16}, "RGB 16"},
        {{PNG_COLOR_TYPE_RGB, 16, false, true}, "RGB 16 tRNS"},
        {{PNG_COLOR_TYPE_RGBA, 8}, "RGBA 8"},
        {{PNG_COLOR_TYPE_RGBA, 16}, "RGBA 16"},
        {{PNG_COLOR_TYPE_RGBA, 16, true}, "RGBA 16 interlaced"},
        {{PNG_COLOR_TYPE_PALETTE, 1}, "palette 1"},
        {{PNG_COLOR_TYPE_PALETTE, 2, false, true}, "palette 2 tRNS"},
        {{PNG_COLOR_TYPE_PALETTE, 4}, "palette 4"},
        {{PNG_COLOR_TYPE_PALETTE, 8}, "palette 8"},
        {{PNG_COLOR_TYPE_PALETTE, 8, true, true}, "palette 8 tRNS interlaced"},
    };
    for (const auto& [spec, what] : specs) {
        const std::string bytes = write_png_bytes(37, 23, spec);
        for (bool alpha_only : {false, true}) {
            Texture t, ref;
            ASSERT_NO_FATAL_FAILURE(decode_both(bytes, "t.png", alpha_only, 37, 23, what, t, ref));
            EXPECT_EQ(t.has_alpha(), ref.has_alpha()) << what;
            const std::vector<vec4> a = t.texels(), b = ref.texels();
            size_t differ = 0;
            for (size_t i = 0; i < a.size(); ++i) {
                differ += a[i] != b[i];
            }
            EXPECT_EQ(differ, 0u) << what << (alpha_only ? " (alpha only)" : "");
        }
    }
}

// Two conforming JPEG decoders differ by rounding only: the accurate integer IDCT of each (stb's is a port of
// libjpeg's jidctint) within 1 of the exact IDCT (IEEE 1180), and YCbCr to RGB and the triangle-filter chroma
// upsampling each rounded once with different fixed-point precision: at most 3 codes a channel.
TEST(TextureDecode, JpegDecodesAsStbImageDidWithinRounding) {
    const std::vector<std::pair<JpegSpec, const char*>> specs = {
        {{JCS_RGB, false, true}, "YCbCr 4:2:0 baseline"},   {{JCS_RGB, false, false}, "YCbCr 4:4:4 baseline"},
        {{JCS_RGB, true, true}, "YCbCr 4:2:0 progressive"}, {{JCS_GRAYSCALE, false, false}, "grey baseline"},
        {{JCS_GRAYSCALE, true, false}, "grey progressive"}, {{JCS_CMYK, false, false}, "Adobe YCCK"},
    };
    std::vector<std::pair<std::string, std::string>> files;
    for (const auto& [spec, what] : specs) files.emplace_back(write_jpeg_bytes(61, 43, spec), what);
    std::string stb_jpg;  // and one from stb_image_write's encoder
    const std::vector<unsigned char> rgb = test_pixels(61, 43, 3, 1, 5);
    stbi_write_jpg_to_func(
        [](void* to, void* data, int n) {
            static_cast<std::string*>(to)->append(static_cast<const char*>(data), size_t(n));
        },
        &stb_jpg, 61, 43, 3, rgb.data(), 80);
    files.emplace_back(stb_jpg, "stb_image_write");
    for (const auto& [bytes, what] : files) {
        for (bool alpha_only : {false, true}) {
            Texture t, ref;
            ASSERT_NO_FATAL_FAILURE(decode_both(bytes, "t.jpg", alpha_only, 61, 43, what, t, ref));
            const std::vector<vec4> a = t.texels(), b = ref.texels();
            int worst = 0;
            double sum = 0;
            for (size_t i = 0; i < a.size(); ++i)
                for (int c = 0; c < 3; ++c) {
                    const int d = std::abs(code_of(a[i][c]) - code_of(b[i][c]));
                    worst = std::max(worst, d);
                    sum += d;
                }
            EXPECT_LE(worst, 3) << what;
            EXPECT_LT(sum / double(3 * a.size()), 0.5) << what;
            for (size_t i = 0; i < a.size(); ++i)  // no alpha in a JPEG: opaque, or the grey level for a mask
                ASSERT_NEAR(a[i].w, alpha_only ? b[i].w : 1.f, 3.f / 255.f) << what;
        }
    }
}

// ---------------------------------------------------------------- damaged files

TEST(TextureDecode, TruncatedJpegAndPngWarnAndKeepTheirFirstRows) {
    const std::string jpg = write_jpeg_bytes(64, 64, JpegSpec{});
    const std::string png = write_png_bytes(64, 64, PngSpec{});
    for (const auto& [bytes, name] : {std::pair{jpg, "cut.jpg"}, std::pair{png, "cut.png"}}) {
        const Texture whole = Texture::decode(bytes, name);
        std::vector<std::string> warnings;
        Texture t;
        ASSERT_NO_THROW(t = Texture::decode(bytes.substr(0, bytes.size() * 6 / 10), name, false, &warnings)) << name;
        ASSERT_EQ(warnings.size(), 1u) << name;
        EXPECT_TRUE(contains(warnings[0], name) && contains(warnings[0], "ends early")) << warnings[0];
        // The first rows are all there (stored top down; a JPEG's first 16-row MCU row but its last row, whose
        // chroma is interpolated with the next MCU row's); the last are not.
        const std::vector<vec4> a = t.texels(), b = whole.texels();
        for (size_t i = 0; i < 64 * 15; ++i) ASSERT_EQ(a[i], b[i]) << name << " texel " << i;
        size_t differ = 0;
        for (size_t i = 64 * 60; i < a.size(); ++i) differ += a[i] != b[i];
        EXPECT_GT(differ, 64u) << name;
    }
    // Cut inside the header: nothing to decode, an error naming the file.
    for (const auto& [bytes, name] : {std::pair{jpg, "head.jpg"}, std::pair{png, "head.png"}}) {
        try {
            Texture::decode(bytes.substr(0, 30), name);
            ADD_FAILURE() << name << " loaded";
        } catch (const Error& e) {
            EXPECT_TRUE(contains(e.what(), std::string(name) + ": cannot read image: ")) << e.what();
        }
    }
}

std::string decode_error(const std::string& bytes, const std::string& name) {
    try {
        Texture::decode(bytes, name);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(TextureDecode, CorruptJpegAndPngGiveAnErrorNamingTheFile) {
    // JPEG: the frame header's sample precision (byte 0 of SOF0's payload) 8 -> 7.
    std::string jpg = write_jpeg_bytes(32, 32, JpegSpec{});
    const size_t sof = jpg.find("\xff\xc0");
    ASSERT_NE(sof, std::string::npos);
    jpg[sof + 4] = 7;
    std::string e = decode_error(jpg, "bad.jpg");
    EXPECT_TRUE(contains(e, "bad.jpg: cannot read image: corrupt or unsupported JPEG data (libjpeg: ")) << e;
    // PNG: a byte of the compressed data changed (the chunk's CRC no longer matches).
    std::string png = write_png_bytes(32, 32, PngSpec{});
    const size_t idat = png.find("IDAT");
    ASSERT_NE(idat, std::string::npos);
    png[idat + 10] = char(png[idat + 10] ^ 0x55);
    e = decode_error(png, "bad.png");
    EXPECT_TRUE(contains(e, "bad.png: cannot read image: corrupt or unsupported PNG data (libpng: ")) << e;
    // A JPEG whose entropy-coded data is damaged decodes with a warning (libjpeg decodes through it); never a crash.
    std::string scrambled = write_jpeg_bytes(64, 64, JpegSpec{});
    const size_t sos = scrambled.find("\xff\xda");
    ASSERT_NE(sos, std::string::npos);
    for (size_t i = sos + 40; i < scrambled.size() - 40; i += 17) scrambled[i] = char(0xff);
    std::vector<std::string> warnings;
    try {
        Texture::decode(scrambled, "scrambled.jpg", false, &warnings);
        ASSERT_EQ(warnings.size(), 1u);
        EXPECT_TRUE(contains(warnings[0], "scrambled.jpg: corrupt JPEG data")) << warnings[0];
    } catch (const Error& err) {
        EXPECT_TRUE(contains(err.what(), "scrambled.jpg: cannot read image: ")) << err.what();
    }
}

// stb_image decodes anything after FF D8 (SOI) as a JPEG, skipping bytes to the next marker: such a file must go to
// libjpeg too (it decodes it, warning of the skipped bytes), never to stb's JPEG decoder.
TEST(TextureDecode, JunkAfterTheJpegStartMarkerStillGoesToLibjpeg) {
    const std::string jpg = write_jpeg_bytes(32, 32, JpegSpec{});
    const std::string junk = jpg.substr(0, 2) + std::string("\x01\x02\x03", 3) + jpg.substr(2);
    std::vector<std::string> warnings;
    const Texture t = Texture::decode(junk, "junk.jpg", false, &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(contains(warnings[0], "junk.jpg: corrupt JPEG data") && contains(warnings[0], "libjpeg"))
        << warnings[0];
    EXPECT_EQ(t.texels(), Texture::decode(jpg, "t.jpg").texels());
}

// ---------------------------------------------------------------- the budget

TEST(TextureDecode, DeclaredSizeOverTheBudgetIsRefusedBeforeDecoding) {
    const ImageLimits saved = image_limits();
    set_image_limits(ImageLimits{1000});  // the files below are 64 x 64 = 4096 pixels
    const std::string jpg = decode_error(write_jpeg_bytes(64, 64, JpegSpec{}), "big.jpg");
    const std::string png = decode_error(write_png_bytes(64, 64, PngSpec{}), "big.png");
    set_image_limits(saved);
    for (const std::string& e : {jpg, png})
        EXPECT_TRUE(contains(e, ": the image declares 64x64 pixels") && contains(e, "--max-image-megapixels")) << e;
    EXPECT_TRUE(contains(jpg, "big.jpg")) << jpg;
    EXPECT_TRUE(contains(png, "big.png")) << png;
}

// A 69-byte PNG declaring 50000 x 50000 pixels (10 GB as RGBA) in a valid IHDR, and no image data: refused from its
// header (far more pixels than 69 bytes can hold), within a few megabytes, where decoding it would allocate first.
TEST(TextureDecode, TinyPngDeclaringAHugeImageIsRefusedWithinLittleMemory) {
    std::string png = write_png_bytes(1, 1, PngSpec{});
    const size_t ihdr = png.find("IHDR");
    ASSERT_NE(ihdr, std::string::npos);
    for (size_t o : {ihdr + 4, ihdr + 8}) {  // width, height: 50000 big-endian
        png[o] = 0, png[o + 1] = 0, png[o + 2] = char(0xc3), png[o + 3] = 0x50;
    }
    const uLong crc = crc32(crc32(0, nullptr, 0), reinterpret_cast<const Bytef*>(png.data() + ihdr), 17);
    for (int k = 0; k < 4; ++k) png[ihdr + 17 + size_t(k)] = char((crc >> (24 - 8 * k)) & 0xff);
    ASSERT_EQ(png.size(), 69u);
    const test::ChildResult idle = test::run_bounded([] { return 0; });
    const test::ChildResult r = test::run_bounded([&] {
        const std::string e = decode_error(png, "huge.png");
        std::fprintf(stderr, "%s\n", e.c_str());
        return contains(e, "huge.png") && contains(e, "declares") ? 0 : 2;
    });
    ASSERT_TRUE(r.finished);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_LT(r.max_rss_kb - idle.max_rss_kb, 64 * 1024);
}

}  // namespace
}  // namespace pv
