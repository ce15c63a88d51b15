// core/image/image_io.h: writing and reading images. EXR is linear FLOAT RGB with string metadata; PNG is the image
// through a view transform (core/image/view_transform.h: exposure, clamp by default, display encoding) in 8 bits.
// Writes go through write_file_atomically (core/base/file_io.h): every write checked, then rename(), so a crash or a
// full disk never leaves half a file. Failures throw pv::Error naming the file.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/image/film.h"
#include "core/image/view_transform.h"

namespace pv {

using Metadata = std::map<std::string, std::string>;

// The memory budget for one image read from a file (environment map or texture). The default, 135 megapixels,
// admits a 16384x8192 environment map (2^27 pixels: 2 GiB as a Texture's 16-byte texels); `pathview
// --max-image-megapixels` changes it. Process-wide, set once at start-up. Reading untrusted images is bounded by it:
// the declared size is read first (the EXR header, stbi_info) and an image larger than the budget, or declaring far
// more pixels than its file could hold, is refused before its pixels are allocated.
struct ImageLimits {
    uint64_t max_pixels = 135'000'000;
};
ImageLimits image_limits();
void set_image_limits(const ImageLimits& limits);
// Refuses (pv::Error naming `path`) a declared size over the budget, or one a file of `file_size` bytes cannot
// hold in its format: at most `pixels_per_byte` pixels per file byte, plus 65536 pixels of slack.
void check_declared_size(const std::string& path, int64_t width, int64_t height, uint64_t file_size,
                         double pixels_per_byte);
// EXR compression (ZIP, PIZ, RLE of long runs) reaches about 1000 pixels per byte on constant images; 4096 leaves
// a margin while a 600-byte file can still not declare more than 2.5 million pixels.
constexpr double kExrPixelsPerByte = 4096.0;

void write_exr(const std::string& path, const Image& image, const Metadata& metadata = {});
// Reads R, G, B (FLOAT or HALF) of an EXR; metadata strings into *metadata when given.
// Regular files only, within the budget of image_limits().
Image read_exr(const std::string& path, Metadata* metadata = nullptr);
// R, G, B of an EXR as RGBA texels (alpha 1), row 0 at the top: the environment-map path, 16 bytes a pixel with
// no intermediate copy. Same checks as read_exr.
std::vector<vec4> read_exr_rgba(const std::string& path, int& width, int& height);
// The same from the bytes of an EXR file in memory; `name` is used in messages.
std::vector<vec4> decode_exr_rgba(const std::string& bytes, const std::string& name, int& width, int& height);
// The image through `transform` (display_bytes) as an 8-bit RGB PNG.
void write_png(const std::string& path, const Image& image, const DisplayTransform& transform = {});
// 8-bit RGB bytes (row 0 at the top) as a PNG.
void write_png_bytes(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb8);
// Writes by extension: .exr (linear: `transform` is not applied) or .png; anything else is an error.
void write_image(const std::string& path, const Image& image, const Metadata& metadata = {},
                 const DisplayTransform& transform = {});

// sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
float linear_to_srgb(float x);

}  // namespace pv
