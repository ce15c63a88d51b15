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

}  // namespace pv
