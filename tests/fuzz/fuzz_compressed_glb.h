// tests/fuzz/fuzz_compressed_glb.h: the .glb the decompressor fuzzers (fuzz_meshopt, fuzz_draco) wrap their input
// in: a JSON chunk naming the compressed data, and the fuzzer's bytes as the BIN chunk, so that every input goes
// through the glTF loader's checks and decoders as a downloaded file would.
#pragma once

#include <cstdint>
#include <string>

namespace pv_fuzz {

inline std::string glb(std::string json, const std::string& bin) {
    while (json.size() % 4) json += ' ';
    std::string padded = bin;
    while (padded.size() % 4) padded += '\0';
    std::string out = "glTF";
    auto u32 = [&out](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(uint32_t(12 + 8 + json.size() + 8 + padded.size()));
    u32(uint32_t(json.size()));
    u32(0x4E4F534Au);
    out += json;
    u32(uint32_t(padded.size()));
    u32(0x004E4942u);
    out += padded;
    return out;
}

}  // namespace pv_fuzz
