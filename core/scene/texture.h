// core/scene/texture.h: 2D image textures for base colour (map_Kd) and alpha (map_d, or map_Kd's alpha channel).
// Linear values (8-bit colour images are sRGB-decoded on load; HDR images are already linear); bilinear
// lookup, wrapping per axis as glTF's samplers do (repeat, the default and OBJ's; clamp to edge; mirrored repeat).
// uv follows OBJ: v = 0 is the bottom row of the image.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/base/math.h"

namespace pv {

// The texels a bilinear lookup reads (indices into the texture's storage) and their weights, as Texture::prefetch
// finds them for Texture::lookup: the address is computed once per lookup.
struct TexelFootprint {
    size_t index[4] = {0, 0, 0, 0};
    float tx = 0.f, ty = 0.f;
    bool valid = false;  // false for a non-finite uv (the lookup then returns texel 0)
};

// The repeat wrap of a texel index, i mod n in [0, n) for n > 0, with magic = wrap_magic(n) (2^64 / n rounded up;
// 0 for n <= 0). A mask for a power-of-two n; otherwise, for |i| < 2^32, Lemire, Kaser and Kurz's fastmod (2019),
// exact for every 32-bit numerator and divisor: the low 64 bits of magic * |i| are the fraction |i| / n, and their
// product with n, shifted down 64 bits, is the remainder. No branch on whether i is already in [0, n): tiled uvs
// (floors, walls) fall on either side of it at random, and a 64-bit division on one side made the wrap the
// slowest part of finding the texels (microbench/texture_wrap.cpp).
inline uint64_t wrap_magic(int n) { return n > 0 ? ~uint64_t(0) / uint64_t(n) + 1 : 0; }
inline size_t wrap_texel_index(long long i, int n, uint64_t magic) {
    if ((n & (n - 1)) == 0) return static_cast<size_t>(i & (n - 1));
    const unsigned long long a = i < 0 ? 0ull - static_cast<unsigned long long>(i) : static_cast<unsigned long long>(i);
    if (a >> 32) {
        const long long r = i % n;
        return static_cast<size_t>(r < 0 ? r + n : r);
    }
    const uint64_t fraction = magic * a;
    const auto r = static_cast<size_t>((static_cast<unsigned __int128>(fraction) * uint64_t(n)) >> 64);
    return i >= 0 || r == 0 ? r : size_t(n) - r;
}

// How a lookup wraps texel indices outside [0, n) on one axis: glTF's sampler wrapS / wrapT (OpenGL's meaning).
// Repeat: i mod n. ClampToEdge: the edge texel, min(max(i, 0), n - 1). MirroredRepeat: period 2n, the second half
// mirrored: k = i mod 2n, then k < n ? k : 2n - 1 - k.
enum class TextureWrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };

// Storage: a texture whose every texel is an 8-bit sRGB code (what an 8-bit image decodes to) is stored as those
// codes, 4 bytes a texel instead of 16, and decoded per lookup through a 256-entry table: the same values, a quarter
// of the memory traffic. The codes are tiled: 4x4 texels to a 64-byte block, one cache line, so a bilinear footprint
// touches 1.56 lines on average instead of 2.1 (and one page more rarely two), where rows of a wide image are a page
// apart. Texels are immutable after construction and shared by copies of a Texture; pack_texels moves a scene's
// textures into one region on huge pages (core/base/huge_pages.h), where a hit's texel reads rarely wait for a page
// walk.
class Texture {
public:
    Texture() = default;
    // Largest texel value kept: larger ones are clamped, negative ones set to 0, non-finite texels to (0, 0, 0, 1).
    static constexpr float kMaxTexel = 1e20f;
    // Builds from linear RGBA texels, row 0 at the top (sanitised as above).
    Texture(int width, int height, std::vector<vec4> texels);
    // From 8-bit texels as image files hold them: R, G, B (sRGB codes) and A (linear) from the low byte up, kept as
    // they are (a lookup decodes them; the same values as the float constructor gives for their decodings).
    Texture(int width, int height, std::vector<uint32_t> codes);

    // Image files (core/scene/texture_decode.cpp, which is the untrusted part; texture_decode.h finds the files).
    // Loads JPEG (libjpeg-turbo), PNG (libpng) and TGA/BMP/PSD/GIF/PNM (stb_image) as sRGB colour and linear alpha,
    // Radiance HDR (linear) through stb_image after checking its run-length data, or EXR (linear RGB, negatives and
    // NaN set to 0) through OpenEXR. The format is told by the file's first bytes. Regular files only; the declared
    // size is checked against the budget (core/image/image_io.h: image_limits()) before pixels are allocated.
    // alpha_only: the texture is a mask (map_d): alpha = its alpha channel if it has one, else its raw grey level.
    // Throws pv::Error naming the file when it cannot be read; a file whose data ends early loads with its
    // missing pixels black (a JPEG's: what libjpeg fills in) and a warning appended to *warnings (when given).
    static Texture load(const std::string& path, bool alpha_only = false, std::vector<std::string>* warnings = nullptr);

    // The same from the bytes of an image file in memory; `name` is used in messages (the fuzzer, tests).
    static Texture decode(std::string bytes, const std::string& name, bool alpha_only = false,
                          std::vector<std::string>* warnings = nullptr);

    vec4 lookup(vec2 uv) const;  // bilinear, wrapped as wrap_s() and wrap_t() say (repeat unless set)
    // Starts loading the texels lookup(uv) reads into the cache without waiting for them (no effect on results): a
    // caller with other work to do before the lookup (a shadow ray to trace) hides the cache miss behind it. Returns
    // their footprint, for lookup(footprint) = lookup(uv), the same bits.
    TexelFootprint prefetch(vec2 uv) const;
    vec4 lookup(const TexelFootprint& footprint) const;
    int width() const { return m_width; }
    int height() const { return m_height; }
    bool has_alpha() const { return m_has_alpha; }
    // The wrap along u (s, the image's columns) and v (t, its rows); both Repeat unless set. Chosen once per
    // texture: a lookup of a texture that repeats on both axes takes the repeat path with no test per texel.
    void set_wrap(TextureWrap s, TextureWrap t) {
        m_wrap_s = s;
        m_wrap_t = t;
        m_repeat = s == TextureWrap::Repeat && t == TextureWrap::Repeat;
    }
    TextureWrap wrap_s() const { return m_wrap_s; }
    TextureWrap wrap_t() const { return m_wrap_t; }
    size_t bytes() const { return m_blocks ? m_count * sizeof(CodeBlock) : m_texels ? m_count * sizeof(vec4) : 0; }
    // Where the texels are (pack_texels, tests): the first byte of their storage, or null for an empty texture.
    const void* storage() const { return m_blocks ? static_cast<const void*>(m_blocks.get()) : m_texels.get(); }
    // The linear texels, row 0 at the top (decoded from the 8-bit codes when kept as codes).
    std::vector<vec4> texels() const;

    // Where texel (x, y) (row y from the top) of a width x height image lies in the tiled code storage: 4x4 blocks
    // of 16 codes (row-major within the block), the blocks row-major, ceil(width / 4) to a row of blocks.
    static size_t tiled_index(size_t x, size_t y, size_t blocks_per_row) {
        return ((y >> 2) * blocks_per_row + (x >> 2)) * 16 + (y & 3) * 4 + (x & 3);
    }

private:
    friend void pack_texels(std::vector<Texture>& textures);
    struct alignas(64) CodeBlock {
        uint32_t code[16];
    };
    bool empty() const { return !m_blocks && !m_texels; }  // no texels (also once moved from)
    vec4 texel(size_t i) const;
    TexelFootprint footprint(vec2 uv) const;
    void tile(const std::vector<uint32_t>& codes);
    int m_width = 0, m_height = 0;
    uint64_t m_wrap_x = 0, m_wrap_y = 0;  // wrap_magic(m_width), wrap_magic(m_height)
    size_t m_blocks_per_row = 0;
    bool m_has_alpha = false;
    bool m_repeat = true;  // m_wrap_s and m_wrap_t both Repeat
    TextureWrap m_wrap_s = TextureWrap::Repeat, m_wrap_t = TextureWrap::Repeat;
    // The storage, shared by copies (it never changes) and owned through the pointers: a vector of the texture's
    // own, or a region shared with the scene's other textures (pack_texels). One of the two is set, or neither.
    std::shared_ptr<const vec4> m_texels;       // linear texels, row-major, when not every texel is an 8-bit code
    std::shared_ptr<const CodeBlock> m_blocks;  // else the codes, tiled: R, G, B (sRGB codes), A (linear), low byte up
    size_t m_count = 0;                         // texels in m_texels or blocks in m_blocks
};

// Moves the texels of all `textures` into one region (allocate_region: on huge pages from 1 MiB up) that they share
// from then on, each texture's storage 64-byte aligned in it. Lookups return the same bits; copies made before keep
// the storage they had. Called once a scene is complete, by load_scene and set_environment_map (core/load/scene_file.h;
// not concurrent with lookups).
void pack_texels(std::vector<Texture>& textures);

// The linear value of 8-bit sRGB code c in [0, 255] (IEC 61966-2-1), as 8-bit images are decoded.
float srgb_code_to_linear(int c);

}  // namespace pv
