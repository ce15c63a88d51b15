// core/load/gltf_compression.h: compressed glTF geometry, decoded into plain buffers before the loader reads the
// meshes: EXT_meshopt_compression (buffer views, through meshoptimizer's decoders and filters) and
// KHR_draco_mesh_compression (primitives, through Draco's decoder). KHR_mesh_quantization needs nothing here: the
// accessors read integer and normalized components in every case (core/load/gltf_internal.h).
// Private to the glTF loader (it works on the loader's tinygltf model).
#pragma once

#include <cstdint>
#include <string>

namespace pv::gltf_detail {

struct Loader;

// Decoded bytes (meshopt views and Draco primitives together) allowed per byte of the file's buffers, and at least
// kMinDecodedBytes: both codecs compress geometry well below 1:64, so a valid file stays far inside; a small file
// that declares gigabytes is refused before they are allocated (meshopt) or right after the decoder returns (Draco,
// whose decoder allocates what its stream's header declares).
inline constexpr uint64_t kDecodedPerByte = 128;
inline constexpr uint64_t kMinDecodedBytes = uint64_t(1) << 26;

// Before tinygltf reads the file, what tinygltf 2.7 would refuse in a valid compressed file: EXT_meshopt_compression's
// fallback buffers (no uri: a loader that decodes the extension never reads them) become 1-byte data URIs, and a
// KHR_draco_mesh_compression primitive's "indices" (an accessor without a bufferView: the indices come from the
// Draco stream) are dropped. `bytes` is the .gltf or .glb; when it changes, the changed file is written to `out` and
// true returned. A file that names neither extension is not parsed (it pays two substring searches); one that does
// has its JSON's shape bounded first (json_bounds.h: an Error naming `file`), as the loader's own parse does.
bool compressed_json_fixups(const std::string& bytes, const std::string& file, std::string& out);

// After tinygltf: every EXT_meshopt_compression buffer view decoded into a new buffer (the view then points at it),
// every KHR_draco_mesh_compression primitive decoded into new float accessors and 32-bit indices. Malformed data
// (truncated streams, counts past a buffer, unknown attribute ids, decoded sizes over the budget) ends in
// Loader::fail: one line naming the file and the JSON pointer.
void decompress(Loader& L);

}  // namespace pv::gltf_detail
