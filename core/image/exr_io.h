// core/image/exr_io.h: writing OpenEXR files whole, for the core files that build their own headers (RGB images,
// AOV layers, partial renders). Core-internal: it exposes OpenEXR types, which stay private to pathview_core.
#pragma once

#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <functional>
#include <string>

namespace pv {

// Writes `path` with `header` through write_file_atomically (core/base/file_io.h): a temporary file, every write
// checked, fsync, close, rename. `fill` sets the OutputFile's frame buffer and writes the pixels. On any failure,
// pv::Error names `path` and the reason, and nothing is left at `path`.
void write_exr_atomically(const std::string& path, const Imf::Header& header,
                          const std::function<void(Imf::OutputFile&)>& fill);

// Opens the EXR `path` for reading with the checks every untrusted EXR gets (a regular file only, the header
// walked and its declared sizes checked against the file's size and the image budget before OpenEXR allocates
// anything; see core/image/image_io.h) and passes it to `read`. OpenEXR's exceptions become pv::Error naming `path`;
// `what` completes "expected ..." in messages ("an EXR image", "a partial render EXR").
void read_exr_guarded(const std::string& path, const std::function<void(Imf::InputFile&)>& read,
                      const char* what = "an EXR image");

}  // namespace pv
