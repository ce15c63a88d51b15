// core/texture.cpp: stb_image loading, sRGB decoding and bilinear lookup.
#include "core/texture.h"

#include "core/error.h"

#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <cctype>
#include <filesystem>

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

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

}  // namespace

float srgb_code_to_linear(int c) { return srgb_table()[std::clamp(c, 0, 255)]; }

Texture::Texture(int width, int height, std::vector<vec4> texels)
    : m_width(width), m_height(height), m_texels(std::move(texels)) {
    for (const vec4& t : m_texels)
        if (t.w < 1.f) {
            m_has_alpha = true;
            break;
        }
    // Keep 8-bit codes instead when every texel is one exactly (bit for bit, so lookups return the same values).
    std::vector<uint32_t> codes(m_texels.size());
    for (size_t i = 0; i < m_texels.size(); ++i) {
        const vec4& t = m_texels[i];
        const int r = srgb_code(t.x), g = srgb_code(t.y), b = srgb_code(t.z), a = alpha_code(t.w);
        if ((r | g | b | a) < 0) return;
        codes[i] = uint32_t(r) | uint32_t(g) << 8 | uint32_t(b) << 16 | uint32_t(a) << 24;
    }
    m_codes = std::move(codes);
    m_texels = std::vector<vec4>();
}

inline vec4 Texture::texel(size_t i) const {
    if (m_codes.empty()) return m_texels[i];
    const float* table = srgb_table();
    const uint32_t c = m_codes[i];
    return vec4(table[c & 0xffu], table[(c >> 8) & 0xffu], table[(c >> 16) & 0xffu], float(c >> 24) / 255.f);
}

Texture Texture::load(const std::string& path, bool alpha_only) {
    int w = 0, h = 0, n = 0;
    std::vector<vec4> texels;
    if (stbi_is_hdr(path.c_str())) {
        float* data = stbi_loadf(path.c_str(), &w, &h, &n, 4);
        if (!data) throw Error(path + ": cannot read image: " + (stbi_failure_reason() ? stbi_failure_reason() : "?"));
        texels.resize(size_t(w) * size_t(h));
        for (size_t i = 0; i < texels.size(); ++i)
            texels[i] = vec4(data[4 * i], data[4 * i + 1], data[4 * i + 2], data[4 * i + 3]);
        stbi_image_free(data);
    } else {
        unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 4);
        if (!data) throw Error(path + ": cannot read image: " + (stbi_failure_reason() ? stbi_failure_reason() : "?"));
        float table[256];
        for (int i = 0; i < 256; ++i) table[i] = srgb_to_linear(float(i) / 255.f);
        texels.resize(size_t(w) * size_t(h));
        for (size_t i = 0; i < texels.size(); ++i)
            texels[i] = vec4(table[data[4 * i]], table[data[4 * i + 1]], table[data[4 * i + 2]], float(data[4 * i + 3]) / 255.f);
        if (alpha_only && (n == 1 || n == 3))
            for (size_t i = 0; i < texels.size(); ++i) texels[i].w = float(data[4 * i]) / 255.f;
        stbi_image_free(data);
    }
    for (vec4& t : texels)
        if (!std::isfinite(t.x + t.y + t.z + t.w)) t = vec4(0.f, 0.f, 0.f, 1.f);
    return Texture(w, h, std::move(texels));
}

vec4 Texture::lookup(vec2 uv) const {
    if (m_texels.empty() && m_codes.empty()) return vec4(1.f);
    // Texel centres at (i + 0.5) / width; v flipped because image row 0 is the top.
    const float x = uv.x * float(m_width) - 0.5f;
    const float y = (1.f - uv.y) * float(m_height) - 0.5f;
    if (!std::isfinite(x) || !std::isfinite(y)) return texel(0);
    const float fx = std::floor(x), fy = std::floor(y);
    const float tx = x - fx, ty = y - fy;
    // i mod n in [0, n); no division when i is already in range (uv in [0, 1) but for the last half texel).
    auto wrap = [](long long i, int n) {
        if (i >= 0 && i < n) return static_cast<size_t>(i);
        const long long r = i % n;
        return static_cast<size_t>(r < 0 ? r + n : r);
    };
    const long long ix = static_cast<long long>(fx), iy = static_cast<long long>(fy);
    const size_t x0 = wrap(ix, m_width), x1 = x0 + 1 == size_t(m_width) ? 0 : x0 + 1;
    const size_t y0 = wrap(iy, m_height), y1 = y0 + 1 == size_t(m_height) ? 0 : y0 + 1;
    const size_t w = size_t(m_width);
    return (1.f - ty) * ((1.f - tx) * texel(y0 * w + x0) + tx * texel(y0 * w + x1)) +
           ty * ((1.f - tx) * texel(y1 * w + x0) + tx * texel(y1 * w + x1));
}

std::string resolve_texture_path(const std::string& dir, const std::string& name) {
    namespace fs = std::filesystem;
    std::string clean = name;
    std::replace(clean.begin(), clean.end(), '\\', '/');
    std::error_code ec;
    const fs::path direct = fs::path(dir) / clean;
    if (fs::is_regular_file(direct, ec)) return direct.string();
    // Walk the components, matching each case-insensitively.
    fs::path cur = dir.empty() ? fs::path(".") : fs::path(dir);
    for (const fs::path& part : fs::path(clean)) {
        if (part.empty() || part == ".") continue;
        const fs::path exact = cur / part;
        if (fs::exists(exact, ec)) {
            cur = exact;
            continue;
        }
        const std::string want = lower(part.string());
        bool found = false;
        for (fs::directory_iterator it(cur, ec), end; !ec && it != end; it.increment(ec)) {
            if (lower(it->path().filename().string()) == want) {
                cur = it->path();
                found = true;
                break;
            }
        }
        if (!found) return {};
    }
    return fs::is_regular_file(cur, ec) ? cur.string() : std::string();
}

}  // namespace pv
