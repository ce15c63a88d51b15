// core/scene/texture.cpp: texel storage (sRGB codes, tiled, or linear floats; pack_texels) and bilinear lookup, the
// hot part of shading. Image files into textures: core/scene/texture_decode.cpp.
#include "core/scene/texture.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>

#include "core/base/huge_pages.h"

namespace pv {
namespace {

// sRGB EOTF (IEC 61966-2-1).
float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// The sRGB decoding of the 256 8-bit codes, as Texture::load applies it.
const float* srgb_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_to_linear(float(i) / 255.f);
        return t;
    }();
    return table.data();
}

bool same_bits(float a, float b) {
    uint32_t x, y;
    std::memcpy(&x, &a, 4);
    std::memcpy(&y, &b, 4);
    return x == y;
}

// The 8-bit sRGB code whose decoding is exactly v, or -1. The table is increasing: a bucket of v's value gives the
// first candidate code, and a short walk up finds the first code not below v (a binary search over the 256 codes
// per channel doubled Sponza's load time).
int srgb_code(float v) {
    constexpr int kBuckets = 1024;
    static const std::array<uint8_t, kBuckets + 1> first = [] {
        std::array<uint8_t, kBuckets + 1> f{};
        const float* table = srgb_table();
        int c = 0;
        for (int b = 0; b <= kBuckets; ++b) {
            while (c < 255 && table[c] < float(b) / float(kBuckets)) ++c;
            f[size_t(b)] = uint8_t(c > 0 ? c - 1 : 0);  // one below: bucket edges are rounded
        }
        return f;
    }();
    if (!(v >= 0.f && v <= 1.f)) return -1;
    const float* table = srgb_table();
    int c = first[size_t(v * float(kBuckets))];
    while (c < 255 && table[c] < v) ++c;
    return same_bits(table[c], v) ? c : -1;
}

// The 8-bit code c with c / 255 exactly a (alpha is stored linear), or -1.
int alpha_code(float a) {
    if (!(a >= 0.f && a <= 1.f)) return -1;
    const int c = int(std::lround(a * 255.f));
    return same_bits(float(c) / 255.f, a) ? c : -1;
}

}  // namespace

float srgb_code_to_linear(int c) { return srgb_table()[std::clamp(c, 0, 255)]; }

namespace {

// Storage of `data`'s elements that owns them: null when empty.
template <typename T>
std::shared_ptr<const T> own(std::vector<T> data) {
    if (data.empty()) return nullptr;
    auto v = std::make_shared<std::vector<T>>(std::move(data));
    return std::shared_ptr<const T>(v, v->data());
}

}  // namespace

Texture::Texture(int width, int height, std::vector<vec4> texels)
    : m_width(width), m_height(height), m_wrap_x(wrap_magic(width)), m_wrap_y(wrap_magic(height)) {
    for (vec4& t : texels) {
        // A texel is finite and in [0, kMaxTexel]: bilinear weights of texels near FLT_MAX can round the lookup up
        // to Inf (found by fuzz_image on an EXR holding uninitialised-looking huge values), and an environment
        // map's importance sums stay finite.
        t = std::isfinite(t.x + t.y + t.z + t.w) ? glm::clamp(t, vec4(0.f), vec4(kMaxTexel)) : vec4(0.f, 0.f, 0.f, 1.f);
        m_has_alpha = m_has_alpha || t.w < 1.f;
    }
    // Keep 8-bit codes instead when every texel is one exactly (bit for bit, so lookups return the same values).
    std::vector<uint32_t> codes(texels.size());
    for (size_t i = 0; i < texels.size(); ++i) {
        const vec4& t = texels[i];
        const int r = srgb_code(t.x), g = srgb_code(t.y), b = srgb_code(t.z), a = alpha_code(t.w);
        if ((r | g | b | a) < 0) {
            m_count = texels.size();
            m_texels = own(std::move(texels));
            return;
        }
        codes[i] = uint32_t(r) | uint32_t(g) << 8 | uint32_t(b) << 16 | uint32_t(a) << 24;
    }
    texels = std::vector<vec4>();
    tile(codes);
}

Texture::Texture(int width, int height, std::vector<uint32_t> codes)
    : m_width(width), m_height(height), m_wrap_x(wrap_magic(width)), m_wrap_y(wrap_magic(height)) {
    for (const uint32_t c : codes)
        if ((c >> 24) < 255u) {
            m_has_alpha = true;
            break;
        }
    tile(codes);
}

void Texture::tile(const std::vector<uint32_t>& codes) {
    if (codes.empty()) return;
    const size_t w = size_t(m_width), h = size_t(m_height);
    m_blocks_per_row = (w + 3) / 4;
    std::vector<CodeBlock> blocks(m_blocks_per_row * ((h + 3) / 4), CodeBlock{});
    for (size_t y = 0; y < h; ++y)
        for (size_t x = 0; x < w; ++x) {
            const size_t i = tiled_index(x, y, m_blocks_per_row);
            blocks[i >> 4].code[i & 15] = codes[y * w + x];
        }
    m_count = blocks.size();
    m_blocks = own(std::move(blocks));
}

void pack_texels(std::vector<Texture>& textures) {
    // Each texture's storage at a 64-byte boundary (a code block is one cache line).
    auto padded = [](size_t bytes) { return (bytes + 63) / 64 * 64; };
    size_t total = 0;
    for (const Texture& t : textures) total += padded(t.bytes());
    if (total == 0) return;
    const std::shared_ptr<std::byte> region = allocate_region(total);
    size_t offset = 0;
    for (Texture& t : textures) {
        if (t.empty()) continue;
        std::byte* at = region.get() + offset;
        std::memcpy(at, t.storage(), t.bytes());
        offset += padded(t.bytes());
        if (t.m_blocks)
            t.m_blocks = std::shared_ptr<const Texture::CodeBlock>(region, reinterpret_cast<Texture::CodeBlock*>(at));
        else
            t.m_texels = std::shared_ptr<const vec4>(region, reinterpret_cast<vec4*>(at));
    }
    // The textures' own storage, as large as the region, was just freed: glibc keeps it mapped otherwise.
    return_freed_heap_memory();
}

std::vector<vec4> Texture::texels() const {
    if (!m_blocks) return std::vector<vec4>(m_texels.get(), m_texels.get() + m_count);
    const size_t w = size_t(m_width), h = size_t(m_height);
    std::vector<vec4> out(w * h);
    for (size_t y = 0; y < h; ++y)
        for (size_t x = 0; x < w; ++x) out[y * w + x] = texel(tiled_index(x, y, m_blocks_per_row));
    return out;
}

// Texel i of the storage: row-major floats, or the tiled codes decoded.
inline vec4 Texture::texel(size_t i) const {
    if (!m_blocks) return m_texels.get()[i];
    const float* table = srgb_table();
    const uint32_t c = m_blocks.get()[i >> 4].code[i & 15];
    return vec4(table[c & 0xffu], table[(c >> 8) & 0xffu], table[(c >> 16) & 0xffu], float(c >> 24) / 255.f);
}

namespace {

// The texel indices of a bilinear pair along one axis, f and f + 1 for f the floor of the (finite) texel coordinate,
// wrapped by `mode` into [0, n): the textures that do not repeat on both axes (glTF samplers) come here.
void wrapped_pair(float f, int n, TextureWrap mode, uint64_t magic, size_t& i0, size_t& i1) {
    switch (mode) {
        case TextureWrap::Repeat: {
            const auto i = static_cast<long long>(std::fabs(f) < 0x1p62f ? f : std::fmod(f, float(n)));
            i0 = wrap_texel_index(i, n, magic);
            i1 = i0 + 1 == size_t(n) ? 0 : i0 + 1;
            return;
        }
        case TextureWrap::ClampToEdge: {
            // Clamped as a float first: any finite f, however large, becomes an index in [-1, n].
            const auto i = static_cast<long long>(std::clamp(f, -1.f, float(n)));
            i0 = size_t(std::clamp<long long>(i, 0, n - 1));
            i1 = size_t(std::clamp<long long>(i + 1, 0, n - 1));
            return;
        }
        case TextureWrap::MirroredRepeat: {
            // Period 2n: beyond 2^62 f is a whole number, and fmod in double reduces it exactly (2n is exact there).
            const long long p = 2ll * n;
            const auto i = static_cast<long long>(std::fabs(f) < 0x1p62f ? double(f) : std::fmod(double(f), double(p)));
            long long k = i % p;
            if (k < 0) k += p;
            const long long k1 = k + 1 == p ? 0 : k + 1;
            i0 = size_t(k < n ? k : p - 1 - k);
            i1 = size_t(k1 < n ? k1 : p - 1 - k1);
            return;
        }
    }
    i0 = i1 = 0;
}

}  // namespace

// The four texels of a bilinear lookup at uv and their weights; not valid for a non-finite uv.
inline TexelFootprint Texture::footprint(vec2 uv) const {
    TexelFootprint fp;
    // Texel centres at (i + 0.5) / width; v flipped because image row 0 is the top.
    const float x = uv.x * float(m_width) - 0.5f;
    const float y = (1.f - uv.y) * float(m_height) - 0.5f;
    if (!std::isfinite(x) || !std::isfinite(y)) return fp;
    fp.valid = true;
    const float fx = std::floor(x), fy = std::floor(y);
    fp.tx = x - fx;
    fp.ty = y - fy;
    // A finite uv can be beyond the range of long long (a file's uvs or transform): such a float is a whole number,
    // and fmod reduces it exactly to the same residue, so the wrap is still the modulo.
    const auto whole = [](float f, int n) {
        return static_cast<long long>(std::fabs(f) < 0x1p62f ? f : std::fmod(f, float(n)));
    };
    size_t x0, x1, y0, y1;
    if (m_repeat) [[likely]] {  // one test per lookup, the same way for every lookup of this texture
        const long long ix = whole(fx, m_width), iy = whole(fy, m_height);
        x0 = wrap_texel_index(ix, m_width, m_wrap_x), x1 = x0 + 1 == size_t(m_width) ? 0 : x0 + 1;
        y0 = wrap_texel_index(iy, m_height, m_wrap_y), y1 = y0 + 1 == size_t(m_height) ? 0 : y0 + 1;
    } else {
        wrapped_pair(fx, m_width, m_wrap_s, m_wrap_x, x0, x1);
        wrapped_pair(fy, m_height, m_wrap_t, m_wrap_y, y0, y1);
    }
    if (m_blocks) {
        const size_t b = m_blocks_per_row;
        fp.index[0] = tiled_index(x0, y0, b);
        fp.index[1] = tiled_index(x1, y0, b);
        fp.index[2] = tiled_index(x0, y1, b);
        fp.index[3] = tiled_index(x1, y1, b);
        return fp;
    }
    const size_t w = size_t(m_width);
    fp.index[0] = y0 * w + x0;
    fp.index[1] = y0 * w + x1;
    fp.index[2] = y1 * w + x0;
    fp.index[3] = y1 * w + x1;
    return fp;
}

vec4 Texture::lookup(vec2 uv) const {
    if (empty()) return vec4(1.f);
    return lookup(footprint(uv));
}

vec4 Texture::lookup(const TexelFootprint& fp) const {
    if (empty()) return vec4(1.f);
    if (!fp.valid) return texel(0);
    const size_t* i = fp.index;
    const float tx = fp.tx, ty = fp.ty;
    return (1.f - ty) * ((1.f - tx) * texel(i[0]) + tx * texel(i[1])) +
           ty * ((1.f - tx) * texel(i[2]) + tx * texel(i[3]));
}

TexelFootprint Texture::prefetch(vec2 uv) const {
    if (empty()) return {};
    const TexelFootprint fp = footprint(uv);
    if (!fp.valid) return fp;
    for (const size_t k : fp.index) {
        if (m_blocks)
            __builtin_prefetch(m_blocks.get() + (k >> 4));
        else
            __builtin_prefetch(m_texels.get() + k);
    }
    return fp;
}

}  // namespace pv
