// core/image_io.h: writing and reading images. EXR is linear FLOAT RGB with string metadata; PNG is tone-mapped
// (exposure, clamp, sRGB) 8-bit. Writes go to a temporary file in the same folder, then rename(), so a crash
// never leaves half a file. Failures throw pv::Error naming the file.
#pragma once

#include "core/film.h"

#include <functional>
#include <map>
#include <string>

namespace pv {

using Metadata = std::map<std::string, std::string>;

void write_exr(const std::string& path, const Image& image, const Metadata& metadata = {});
// Reads R, G, B (FLOAT or HALF) of an EXR; metadata strings into *metadata when given.
Image read_exr(const std::string& path, Metadata* metadata = nullptr);
// exposure in stops: the image is multiplied by 2^exposure before the sRGB transfer.
void write_png(const std::string& path, const Image& image, float exposure = 0.f);
// Writes by extension: .exr or .png; anything else is an error.
void write_image(const std::string& path, const Image& image, const Metadata& metadata = {});

// Writes `path` through a temporary file in the same folder: write(tmp) creates the temporary, which is then renamed
// to `path`. On failure the temporary is removed and pv::Error names `path`; `path` is never half-written.
void write_via_temporary(const std::string& path, const std::function<void(const std::string& tmp)>& write);

// sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
float linear_to_srgb(float x);

}  // namespace pv
