// core/scene/texture_decode.h: finding the image files a scene names. Decoding them (untrusted bytes: the declared
// size checked against the budget before pixels are allocated, Radiance RLE data walked before stb_image sees it,
// truncation found and warned about) is Texture::load and Texture::decode (core/scene/texture.h), defined with this
// in core/scene/texture_decode.cpp; the lookups they serve stay in core/scene/texture.cpp.
#pragma once

#include <string>

#include "core/scene/texture.h"

namespace pv {

// Finds `name` relative to `dir`: exactly, else a case-insensitive match of each path component (archive scenes
// name "SP_LUK.JPG" for "sp_luk.JPG"). Returns the path found, or an empty string.
std::string resolve_texture_path(const std::string& dir, const std::string& name);

// The bytes of the image file `path`, read only after its first 64 KiB: a file whose header states no size in a
// format we read is refused then; one whose declared size is over the budget (image_limits()) or more than its
// bytes can hold is refused as Texture::decode would; and a file larger than 16 bytes a declared pixel plus 64 MiB
// (metadata) is refused rather than read. (A 1 GB sparse file named as an image was read whole before its header
// was looked at.) EXR and headers past the first 64 KiB: read up to the budget's 16 bytes a pixel plus 64 MiB.
std::string read_image_file(const std::string& path, const char* what);

// The width and height an image file's header declares (stb_image's formats; false for EXR, for anything else it
// cannot read, and past 2 GiB).
bool image_header_size(const unsigned char* bytes, size_t size, int& width, int& height);

}  // namespace pv
