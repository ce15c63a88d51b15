// core/frame/partial.cpp: the partial-render EXR (OpenEXR UINT channels for the exact double sums), its validation,
// the scene identity hash and the merge.
#include "core/frame/partial.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <set>
#include <sstream>
#include <type_traits>
#include <variant>

#include "core/base/error.h"
#include "core/base/version.h"
#include "core/frame/renderer.h"
#include "core/image/exr_io.h"
#include "core/sampling/rng.h"

namespace pv {
namespace {

constexpr const char* kFormat = "1";
const char* const kRgb[3] = {"R", "G", "B"};

// The three double accumulators of a FilmPixel, by layer name.
using Triple = double[3];
struct Plane {
    const char* layer;
    Triple FilmPixel::*field;
};
const Plane kPlanes[] = {{"sum", &FilmPixel::sum}, {"sumsq", &FilmPixel::sum_sq}, {"half", &FilmPixel::sum_even}};
struct CountPlane {
    const char* name;
    uint32_t FilmPixel::*field;
};
const CountPlane kCounts[] = {{"count.n", &FilmPixel::n}, {"count.half", &FilmPixel::n_even}};

// Attributes that make up the identity or are computed on writing; everything else is info.
const std::set<std::string> kReservedKeys = {"pathview:partial",  "pathview:version",         "pathview:scene_hash",
                                             "pathview:settings", "pathview:partial:camera",  "pathview:samples",
                                             "pathview:spp",      "pathview:rel_mse_estimate"};
const char* const kSummedKeys[] = {"pathview:seconds", "pathview:rays", "pathview:dropped_samples"};

std::string hex64(uint64_t v) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
    return buf;
}

// One line: OpenEXR messages may span several.
std::string one_line(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    return s;
}

// Word-at-a-time content hash (SplitMix64 mixing of each 8-byte word, core/sampling/rng.h).
class Hasher {
public:
    void bytes(const void* data, size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (; n >= 8; n -= 8, p += 8) {
            uint64_t w;
            std::memcpy(&w, p, 8);
            m_h = hash_combine(m_h, w);
        }
        uint64_t tail = 0;
        std::memcpy(&tail, p, n);
        m_h = hash_combine(m_h, tail ^ (uint64_t(n) << 56));
    }
    template <class T>
    void value(const T& v) {
        bytes(&v, sizeof v);
    }
    template <class T>
    void vector(const std::vector<T>& v) {
        value(uint64_t(v.size()));
        if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
    }
    void string(const std::string& s) {
        value(uint64_t(s.size()));
        bytes(s.data(), s.size());
    }
    uint64_t get() const { return m_h; }

private:
    uint64_t m_h = 0x7061727469616cull;
};

void hash_material(Hasher& h, const Material& m) {
    h.string(m.name);
    h.value(uint64_t(m.bsdf.index()));
    std::visit(
        [&](const auto& b) {
            using T = std::decay_t<decltype(b)>;
            if constexpr (std::is_same_v<T, Lambertian>) h.value(b.albedo);
            if constexpr (std::is_same_v<T, Mirror>) h.value(b.reflectance);
            if constexpr (std::is_same_v<T, Dielectric>) h.value(b.eta);
            if constexpr (std::is_same_v<T, Glossy>) {
                h.value(b.diffuse);
                h.value(b.specular);
                h.value(b.alpha);
            }
            if constexpr (std::is_same_v<T, MetallicRoughness>) {  // a new type: OBJ hashes are unchanged
                h.value(b.base_color);
                h.value(b.metallic);
                h.value(b.roughness);
                h.value(b.ior);
                h.value(b.specular);
                h.value(b.specular_color);
                h.value(b.transmission);
                h.value(uint8_t(b.thin_walled));
                h.value(b.attenuation_color);
                h.value(b.attenuation_distance);
            }
        },
        m.bsdf);
    h.value(m.emission);
    h.value(uint8_t(m.two_sided_emission));
    h.value(m.base_color_texture);
    h.value(m.alpha_texture);
    if (m.metallic_roughness_texture != kNoIndex) h.value(m.metallic_roughness_texture);  // glTF only
    if (m.normal_texture != kNoIndex) {                                                   // glTF only
        h.value(m.normal_texture);
        h.value(m.normal_scale);
    }
    if (m.emissive_texture != kNoIndex || !m.emissive_uv.is_identity()) {  // glTF only: OBJ hashes as before
        h.value(m.emissive_texture);
        h.value(m.emissive_uv.col0);
        h.value(m.emissive_uv.col1);
        h.value(m.emissive_uv.offset);
        h.value(m.emissive_uv.set);
    }
}

uint64_t parse_u64(const std::string& s, bool& ok) {
    const std::optional<uint64_t> v = parse_decimal(s);
    ok = v.has_value();
    return v.value_or(0);
}

}  // namespace

std::string partial_version() { return std::string("pathview ") + kVersion + ", partial format " + kFormat; }

uint64_t PartialRender::sample_count() const {
    uint64_t n = 0;
    for (const SampleRange& r : ranges) n += r.count;
    return n;
}

std::string format_ranges(const std::vector<SampleRange>& ranges) {
    std::string s;
    for (const SampleRange& r : ranges)
        s += (s.empty() ? "" : ",") + std::to_string(r.start) + ":" + std::to_string(r.count);
    return s;
}

void normalize_ranges(std::vector<SampleRange>& ranges, const std::string& what) {
    std::sort(ranges.begin(), ranges.end(),
              [](const SampleRange& a, const SampleRange& b) { return a.start < b.start; });
    std::vector<SampleRange> out;
    for (const SampleRange& r : ranges) {
        if (!out.empty() && r.start < out.back().end())
            throw Error(what + ": sample ranges " + format_ranges({out.back()}) + " and " + format_ranges({r}) +
                        " overlap");
        if (!out.empty() && r.start == out.back().end())
            out.back().count += r.count;
        else
            out.push_back(r);
    }
    ranges = std::move(out);
}

std::vector<SampleRange> parse_ranges(const std::string& text, const std::string& what) {
    std::vector<SampleRange> out;
    size_t pos = 0;
    while (!text.empty()) {
        const size_t comma = text.find(',', pos);
        const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
        const size_t colon = item.find(':');
        const std::optional<uint64_t> a =
            colon == std::string::npos ? std::nullopt : parse_decimal(item.substr(0, colon), kSampleIndexLimit);
        const std::optional<uint64_t> b =
            colon == std::string::npos ? std::nullopt : parse_decimal(item.substr(colon + 1), kSampleIndexLimit);
        if (!a || !b || *b == 0 || *a + *b > kSampleIndexLimit)
            throw Error(what + ": sample range " + quote_prefix(item) +
                        "; expected START:COUNT (decimal digits, no sign, spaces or leading zeros) with COUNT > 0 "
                        "and START + COUNT <= 2^32, ranges separated by single commas");
        out.push_back({*a, *b});
        if (comma == std::string::npos) break;
        pos = comma + 1;
    }
    if (out.empty()) throw Error(what + ": no sample range; expected START:COUNT[,START:COUNT...]");
    normalize_ranges(out, what);
    return out;
}

void parse_shard(const std::string& text, uint64_t& index, uint64_t& shards) {
    const size_t slash = text.find('/');
    const std::optional<uint64_t> i =
        slash == std::string::npos ? std::nullopt : parse_decimal(text.substr(0, slash), kSampleIndexLimit);
    const std::optional<uint64_t> n =
        slash == std::string::npos ? std::nullopt : parse_decimal(text.substr(slash + 1), kSampleIndexLimit);
    if (!i || !n || *n == 0 || *i >= *n)
        throw Error("--shard " + quote_prefix(text) +
                    ": expected INDEX/COUNT in decimal digits (no sign, spaces or leading zeros) with "
                    "0 <= INDEX < COUNT, e.g. 3/16");
    index = *i;
    shards = *n;
}

SampleRange shard_range(uint64_t index, uint64_t shards, uint64_t total) {
    if (shards == 0 || index >= shards)
        throw Error("--shard " + std::to_string(index) + "/" + std::to_string(shards) +
                    ": expected INDEX/COUNT with 0 <= INDEX < COUNT");
    if (total < shards)
        throw Error("--shard " + std::to_string(index) + "/" + std::to_string(shards) + ": " + std::to_string(total) +
                    " samples cannot fill " + std::to_string(shards) + " shards; use at most " + std::to_string(total) +
                    " shards");
    const uint64_t base = total / shards, extra = total % shards;
    return {index * base + std::min(index, extra), base + (index < extra ? 1u : 0u)};
}

uint64_t scene_hash(const Scene& scene, const std::vector<Material>& materials, const EnvironmentSettings& env) {
    Hasher h;
    h.vector(scene.positions);
    h.vector(scene.triangles);
    h.vector(scene.normals);
    h.vector(scene.normal_indices);
    h.vector(scene.uvs);
    h.vector(scene.uv_indices);
    h.vector(scene.material_ids);
    if (!scene.colors.empty()) {  // vertex colours (glTF COLOR_0) only when present: other scenes hash as before
        h.vector(scene.colors);
        h.vector(scene.color_indices);
    }
    if (!scene.tangents.empty()) {  // glTF TANGENT only when present
        h.vector(scene.tangents);
        h.vector(scene.tangent_indices);
    }
    if (!scene.uvs1.empty() || !scene.punctual_lights.empty()) {  // glTF only: OBJ scenes hash as before
        h.vector(scene.uvs1);
        h.vector(scene.uv1_indices);
        h.value(uint64_t(scene.punctual_lights.size()));
        for (const PunctualLight& l : scene.punctual_lights) {
            h.value(uint8_t(l.type));
            h.value(l.position);
            h.value(l.direction);
            h.value(l.intensity);
            h.value(l.range);
            h.value(l.inner_cone_rad);
            h.value(l.outer_cone_rad);
        }
    }
    h.value(uint64_t(materials.size()));
    for (const Material& m : materials) hash_material(h, m);
    h.value(uint64_t(scene.textures.size()));
    for (const Texture& t : scene.textures) {
        h.value(t.width());
        h.value(t.height());
        h.vector(t.texels());
        if (t.wrap_s() != TextureWrap::Repeat || t.wrap_t() != TextureWrap::Repeat) {  // glTF only: OBJ as before
            h.value(uint8_t(t.wrap_s()));
            h.value(uint8_t(t.wrap_t()));
        }
    }
    h.value(scene.environment_map);
    h.value(env.background);
    h.value(env.rotation_deg);
    h.value(env.strength);
    h.value(env.sun_direction);
    h.value(env.sun_angular_radius_deg);
    h.value(env.sun_irradiance);
    return h.get();
}

std::string camera_text(const CameraDesc& c) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "--eye %.9g,%.9g,%.9g --target %.9g,%.9g,%.9g --up %.9g,%.9g,%.9g --fov %.9g --aperture %.9g "
                  "--focus-distance %.9g",
                  c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.vfov_deg,
                  c.aperture, c.focus_distance);
    return buf;
}

CameraDesc parse_camera(const std::string& text, const std::string& what) {
    CameraDesc c;
    int used = 0;
    const int got = std::sscanf(text.c_str(),
                                "--eye %f,%f,%f --target %f,%f,%f --up %f,%f,%f --fov %f --aperture %f "
                                "--focus-distance %f%n",
                                &c.eye.x, &c.eye.y, &c.eye.z, &c.target.x, &c.target.y, &c.target.z, &c.up.x, &c.up.y,
                                &c.up.z, &c.vfov_deg, &c.aperture, &c.focus_distance, &used);
    if (got != 12 || size_t(used) != text.size() || camera_text(c) != text)
        throw Error(what + ": camera " + quote_prefix(text) +
                    " is malformed; expected --eye x,y,z --target x,y,z --up x,y,z "
                    "--fov f --aperture a --focus-distance d");
    return c;
}

RenderSettings parse_settings(const std::string& text, const std::string& what) {
    RenderSettings s;
    s.sky_guide = SkyGuideMode::Off;  // absent in strings from before the sky guide
    std::stringstream ss(text);
    std::string item;
    bool ok = true;
    while (ok && ss >> item) {
        const size_t eq = item.find('=');
        const std::string key = item.substr(0, eq), value = eq == std::string::npos ? "" : item.substr(eq + 1);
        bool num_ok = false;
        if (key == "nee")
            s.light_sampling = value == "on";
        else if (key == "mis")
            s.mis = value == "on";
        else if (key == "rr")
            s.russian_roulette = value == "on";
        else if (key == "max_depth")
            s.max_depth = int(parse_u64(value, num_ok)), ok = num_ok;
        else if (key == "seed")
            s.seed = uint32_t(parse_u64(value, num_ok)), ok = num_ok;
        else if (key == "sky_guide" && (value == "on" || value == "auto"))
            s.sky_guide = value == "on" ? SkyGuideMode::On : SkyGuideMode::Auto;
        else if (key == "light_sampler" && value == "tree")
            s.light_sampler = LightSamplerKind::Tree;
        else if (key == "sampler" && parse_sampler(value))
            s.sampler = *parse_sampler(value);
        else
            ok = false;
    }
    if (!ok || s.describe() != text)
        throw Error(what + ": settings " + quote_prefix(text) + " are not understood by " + partial_version());
    return s;
}

PartialRender partial_from_renderer(const Renderer& r, std::vector<SampleRange> ranges) {
    PartialRender p;
    p.id.version = partial_version();
    p.id.scene_hash = scene_hash(r.scene(), r.traceable().materials(), r.traceable().environment_settings());
    p.id.settings = r.settings_as_rendered().describe();
    p.id.camera = camera_text(r.camera().desc());
    p.id.width = r.film().width();
    p.id.height = r.film().height();
    normalize_ranges(ranges, "partial render");
    p.ranges = std::move(ranges);
    p.film = r.film();
    p.info = render_metadata(r);
    for (const std::string& k : kReservedKeys) p.info.erase(k);
    p.info.erase("pathview:threads");  // differs between parts and means nothing for the sum
    return p;
}

void add_summed_info(Metadata& into, const Metadata& from) {
    for (const char* key : kSummedKeys) {
        const auto a = into.find(key);
        const auto b = from.find(key);
        if (b == from.end()) continue;
        if (a == into.end()) {
            into[key] = b->second;
            continue;
        }
        bool ok_a = false, ok_b = false;
        const uint64_t ia = parse_u64(a->second, ok_a), ib = parse_u64(b->second, ok_b);
        if (ok_a && ok_b) {
            a->second = std::to_string(ia + ib);
        } else {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.6f", std::atof(a->second.c_str()) + std::atof(b->second.c_str()));
            a->second = buf;
        }
    }
}

namespace {

// Rows per block when reading and writing the pixel planes: memory in proportion to a block, not the image.
constexpr int kBlockRows = 64;

// The UINT channels, in the order of the word planes: each plane's hi and lo words per channel, then the counts.
std::vector<std::string> word_channel_names() {
    std::vector<std::string> names;
    for (const Plane& plane : kPlanes)
        for (int c = 0; c < 3; ++c)
            for (const char* half : {"_hi.", "_lo."}) names.push_back(std::string(plane.layer) + half + kRgb[c]);
    for (const CountPlane& cp : kCounts) names.push_back(cp.name);
    return names;
}

// The largest value one accepted sample adds to a sum (Film::add takes finite float radiance).
constexpr double kMaxSample = double(FLT_MAX) * (1.0 + 1e-9);  // with room for the double sums' rounding

// Whether a pixel's accumulators are what `n` float samples can give: finite, non-negative, each sum at most n
// (n_even) times the largest float, and nothing without samples. Within these bounds every statistic the film
// derives (float mean, variance, half-buffer error estimate) is finite, and so is any sum of merged parts.
bool plausible(const FilmPixel& px, const char*& what) {
    for (int c = 0; c < 3; ++c) {
        const double v[3] = {px.sum[c], px.sum_sq[c], px.sum_even[c]};
        for (int k = 0; k < 3; ++k)
            if (!(std::isfinite(v[k]) && v[k] >= 0.0)) {
                what = kPlanes[k].layer;
                return false;
            }
        if (px.sum[c] > kMaxSample * px.n || px.sum_even[c] > kMaxSample * px.n_even) {
            what = px.sum[c] > kMaxSample * px.n ? "sum" : "half";
            return false;
        }
        if (px.sum_sq[c] > kMaxSample * kMaxSample * px.n) {
            what = "sumsq";
            return false;
        }
    }
    return true;
}

std::string pixel_name(size_t i, int w) {
    return "pixel (" + std::to_string(i % size_t(w)) + ", " + std::to_string(i / size_t(w)) + ")";
}

// The header of an opened partial EXR, checked: identity, ranges, info, channels, compression, size for the file.
PartialRender read_header(const std::string& path, Imf::InputFile& file) {
    PartialRender part;
    const Imf::Header& header = file.header();
    Metadata attrs;
    for (auto it = header.begin(); it != header.end(); ++it)
        if (auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) attrs[it.name()] = s->value();
    auto attr = [&](const char* key) {
        const auto it = attrs.find(key);
        if (it == attrs.end()) throw Error(path + ": attribute " + key + " is missing; the file is damaged");
        return it->second;
    };
    if (!attrs.count("pathview:partial"))
        throw Error(path +
                    ": not a partial render (no pathview:partial attribute); expected a file written by "
                    "`pathview render --samples`, `--resume` or `pathview merge`");
    if (attrs["pathview:partial"] != kFormat || attr("pathview:version") != partial_version())
        throw Error(path + ": written by " + quote_prefix(attrs["pathview:version"]) + " (format " +
                    quote_prefix(attrs["pathview:partial"]) + "); this is " + partial_version() +
                    ", which reads only its own partial renders");

    const Imath::Box2i dw = header.dataWindow();
    const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
    if (dw.min.x != 0 || dw.min.y != 0 || w <= 0 || h <= 0 || w * h > (1l << 28))
        throw Error(path + ": data window is not [0, w) x [0, h) or is too large");
    // pathview writes ZIP; these compress the 92 bytes of a pixel's 23 channels at most 1032:1 (zlib's limit).
    const Imf::Compression compression = header.compression();
    if (compression != Imf::NO_COMPRESSION && compression != Imf::RLE_COMPRESSION &&
        compression != Imf::ZIPS_COMPRESSION && compression != Imf::ZIP_COMPRESSION)
        throw Error(path + ": compression " + std::to_string(int(compression)) +
                    " in a partial render; expected none, RLE, ZIPS or ZIP (pathview writes ZIP)");
    std::error_code ec;
    const uint64_t bytes = std::filesystem::file_size(path, ec);
    if (!ec && double(w) * double(h) > double(bytes) * 12.0 + 65536.0)
        throw Error(path + ": declares " + std::to_string(w) + "x" + std::to_string(h) + " pixels but has only " +
                    std::to_string(bytes) +
                    " bytes (a partial render holds at least 1 byte per 12 pixels); the file is damaged or "
                    "truncated");
    part.id.version = attrs["pathview:version"];
    const std::string hash = attr("pathview:scene_hash");
    part.id.scene_hash = std::strtoull(hash.c_str(), nullptr, 16);
    if (hash.size() != 16 || hash.find_first_not_of("0123456789abcdef") != std::string::npos)
        throw Error(path + ": pathview:scene_hash " + quote_prefix(hash) + " is not 16 hex digits");
    part.id.settings = attr("pathview:settings");
    parse_settings(part.id.settings, path);
    part.id.camera = attr("pathview:partial:camera");
    parse_camera(part.id.camera, path);
    part.id.width = int(w);
    part.id.height = int(h);
    part.ranges = parse_ranges(attr("pathview:samples"), path);
    for (const auto& [k, v] : attrs)
        if (!kReservedKeys.count(k)) part.info[k] = v;
    for (const std::string& name : word_channel_names()) {
        const Imf::Channel* ch = header.channels().findChannel(name);
        if (!ch || ch->type != Imf::UINT) throw Error(path + ": channel " + name + " is missing or not UINT");
    }
    return part;
}

// Reads rows [y0, y1) of an opened partial EXR (checked by read_header) into `px` (w * (y1 - y0) pixels) and
// checks every pixel against the file's sample count. `words` is scratch space, reused between blocks.
void read_rows(const std::string& path, Imf::InputFile& file, const PartialRender& header, int y0, int y1,
               std::vector<std::vector<uint32_t>>& words, std::vector<FilmPixel>& px) {
    const int w = header.id.width;
    const size_t n = size_t(w) * size_t(y1 - y0);
    const std::vector<std::string> names = word_channel_names();
    words.resize(names.size());
    Imf::FrameBuffer fb;
    for (size_t k = 0; k < names.size(); ++k) {
        words[k].resize(n);
        fb.insert(names[k], Imf::Slice::Make(Imf::UINT, words[k].data(), Imath::V2i(0, y0), w, y1 - y0,
                                             sizeof(uint32_t), sizeof(uint32_t) * size_t(w)));
    }
    file.setFrameBuffer(fb);
    file.readPixels(y0, y1 - 1);
    if (y1 == header.id.height && !file.isComplete()) throw Error(path + ": the file is truncated");

    px.assign(n, FilmPixel{});
    size_t k = 0;
    for (const Plane& plane : kPlanes)
        for (int c = 0; c < 3; ++c, k += 2)
            for (size_t i = 0; i < n; ++i) {
                const uint64_t bits = (uint64_t(words[k][i]) << 32) | words[k + 1][i];
                std::memcpy(&(px[i].*plane.field)[c], &bits, 8);
            }
    for (const CountPlane& cp : kCounts) {
        for (size_t i = 0; i < n; ++i) px[i].*cp.field = words[k][i];
        ++k;
    }
    const uint64_t total = header.sample_count();
    const size_t first = size_t(y0) * size_t(w);
    for (size_t i = 0; i < n; ++i) {
        if (px[i].n > total || px[i].n_even > px[i].n)
            throw Error(path + ": " + pixel_name(first + i, w) + " counts " + std::to_string(px[i].n) + " samples (" +
                        std::to_string(px[i].n_even) + " in the first half), more than its " + std::to_string(total) +
                        "; the file is damaged");
        const char* what = "";
        if (!plausible(px[i], what))
            throw Error(path + ": " + pixel_name(first + i, w) + " has a " + what +
                        " that is negative, not finite or larger than its " + std::to_string(px[i].n) +
                        " samples of finite float radiance can give; the file is damaged");
    }
}

// OpenEXR's exceptions as one line naming `path`.
template <class Fn>
void guarded(const std::string& path, Fn&& fn) {
    try {
        read_exr_guarded(path, fn, "a partial render EXR");
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(path + ": out of memory while reading the partial render");
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read EXR: " + one_line(e.what()));
    }
}

// The checks of a merge on the parts' headers: same identity, disjoint ranges. Returns the parts' order (by first
// sample index, so the sums do not depend on the order of the arguments) and sets `out`'s identity, ranges, info.
std::vector<size_t> plan_merge(const std::vector<PartialRender>& parts, const std::vector<std::string>& names,
                               PartialRender& out) {
    if (parts.empty()) throw Error("merge: no partial renders given");
    std::vector<size_t> order(parts.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return parts[a].ranges.front().start < parts[b].ranges.front().start; });

    const PartialRender& first = parts[order[0]];
    const std::string& first_name = names[order[0]];
    out.id = first.id;
    out.info = first.info;
    struct Owned {
        SampleRange range;
        size_t part;
    };
    std::vector<Owned> all;
    for (const SampleRange& r : first.ranges) all.push_back({r, order[0]});
    for (size_t k = 1; k < order.size(); ++k) {
        const PartialRender& p = parts[order[k]];
        const std::string& name = names[order[k]];
        auto mismatch = [&](const std::string& what, const std::string& mine, const std::string& theirs) {
            throw Error(name + ": " + what + " " + quote_prefix(mine) + " differs from " + first_name + "'s " +
                        quote_prefix(theirs) + "; parts of one render must agree");
        };
        if (p.id.version != first.id.version) mismatch("version", p.id.version, first.id.version);
        if (p.id.scene_hash != first.id.scene_hash)
            mismatch("scene (geometry, materials, environment) hash", hex64(p.id.scene_hash),
                     hex64(first.id.scene_hash));
        if (p.id.settings != first.id.settings) mismatch("settings", p.id.settings, first.id.settings);
        if (p.id.camera != first.id.camera) mismatch("camera", p.id.camera, first.id.camera);
        if (p.id.width != first.id.width || p.id.height != first.id.height)
            mismatch("size", std::to_string(p.id.width) + "x" + std::to_string(p.id.height),
                     std::to_string(first.id.width) + "x" + std::to_string(first.id.height));
        for (const SampleRange& r : p.ranges) all.push_back({r, order[k]});
    }
    std::stable_sort(all.begin(), all.end(),
                     [](const Owned& a, const Owned& b) { return a.range.start < b.range.start; });
    for (size_t i = 1; i < all.size(); ++i)
        if (all[i].range.start < all[i - 1].range.end())
            throw Error(names[all[i].part] + ": sample range " + format_ranges({all[i].range}) + " overlaps " +
                        format_ranges({all[i - 1].range}) + " of " + names[all[i - 1].part] +
                        "; each sample index may be merged once");
    for (size_t k = 1; k < order.size(); ++k) add_summed_info(out.info, parts[order[k]].info);
    out.ranges.clear();
    for (const Owned& o : all) out.ranges.push_back(o.range);
    normalize_ranges(out.ranges, "merge");
    return order;
}

// a += b, as Film::merge, refusing (naming `name`, the file of b) a sum that overflows: never a non-finite film.
void add_pixels(FilmPixel* a, const FilmPixel* b, size_t n, size_t first, int w, const std::string& name) {
    for (size_t i = 0; i < n; ++i) {
        FilmPixel& x = a[i];
        const FilmPixel& y = b[i];
        for (int c = 0; c < 3; ++c) {
            x.sum[c] += y.sum[c];
            x.sum_sq[c] += y.sum_sq[c];
            x.sum_even[c] += y.sum_even[c];
        }
        if (uint64_t(x.n) + y.n > UINT32_MAX)
            throw Error(name + ": " + pixel_name(first + i, w) + ": the merged sample count exceeds 2^32 - 1");
        x.n += y.n;
        x.n_even += y.n_even;
        const char* what = "";
        if (!plausible(x, what))
            throw Error(name + ": " + pixel_name(first + i, w) + ": adding this part's " + what +
                        " overflows (not finite or beyond what float samples give); nothing is written");
    }
}

}  // namespace

void write_partial(const std::string& path, const PartialRender& part) {
    const Film& film = part.film;
    const int w = film.width(), h = film.height();
    const std::vector<FilmPixel>& px = film.pixels();
    const std::vector<std::string> names = word_channel_names();

    Metadata attrs = part.info;
    attrs["pathview:partial"] = kFormat;
    attrs["pathview:version"] = part.id.version;
    attrs["pathview:scene_hash"] = hex64(part.id.scene_hash);
    attrs["pathview:settings"] = part.id.settings;
    attrs["pathview:partial:camera"] = part.id.camera;
    attrs["pathview:samples"] = format_ranges(part.ranges);
    attrs["pathview:spp"] = std::to_string(part.sample_count());
    char rel[32];
    std::snprintf(rel, sizeof rel, "%.6g", film.estimated_rel_mse());
    attrs["pathview:rel_mse_estimate"] = rel;

    Imf::Header header(w, h);
    for (const char* c : kRgb) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    for (const std::string& name : names) header.channels().insert(name, Imf::Channel(Imf::UINT));
    for (const auto& [k, v] : attrs) header.insert(k, Imf::StringAttribute(v));
    write_exr_atomically(path, header, [&](Imf::OutputFile& file) {
        // Row blocks: the mean as FLOAT (as Film::mean), each double as its high and low 32-bit words, the counts.
        std::vector<float> rgb;
        std::vector<std::vector<uint32_t>> words(names.size());
        for (int y0 = 0; y0 < h; y0 += kBlockRows) {
            const int rows = std::min(kBlockRows, h - y0);
            const size_t n = size_t(w) * size_t(rows), first = size_t(y0) * size_t(w);
            rgb.resize(3 * n);
            for (auto& v : words) v.resize(n);
            for (size_t i = 0; i < n; ++i) {
                const FilmPixel& p = px[first + i];
                const double inv = p.n ? 1.0 / p.n : 0.0;
                for (int c = 0; c < 3; ++c) rgb[3 * i + c] = static_cast<float>(p.sum[c] * inv);
                size_t k = 0;
                for (const Plane& plane : kPlanes)
                    for (int c = 0; c < 3; ++c, k += 2) {
                        uint64_t bits;
                        std::memcpy(&bits, &(p.*plane.field)[c], 8);
                        words[k][i] = uint32_t(bits >> 32);
                        words[k + 1][i] = uint32_t(bits);
                    }
                for (const CountPlane& cp : kCounts) words[k++][i] = p.*cp.field;
            }
            Imf::FrameBuffer fb;
            for (int c = 0; c < 3; ++c)
                fb.insert(kRgb[c], Imf::Slice::Make(Imf::FLOAT, rgb.data() + c, Imath::V2i(0, y0), w, rows,
                                                    3 * sizeof(float), 3 * sizeof(float) * size_t(w)));
            for (size_t k = 0; k < names.size(); ++k)
                fb.insert(names[k], Imf::Slice::Make(Imf::UINT, words[k].data(), Imath::V2i(0, y0), w, rows,
                                                     sizeof(uint32_t), sizeof(uint32_t) * size_t(w)));
            file.setFrameBuffer(fb);
            file.writePixels(rows);
        }
    });
}

PartialRender read_partial(const std::string& path) {
    PartialRender part;
    guarded(path, [&](Imf::InputFile& file) {
        part = read_header(path, file);
        std::vector<std::vector<uint32_t>> words;
        std::vector<FilmPixel> px, block;
        px.reserve(size_t(part.id.width) * size_t(part.id.height));
        for (int y0 = 0; y0 < part.id.height; y0 += kBlockRows) {
            read_rows(path, file, part, y0, std::min(part.id.height, y0 + kBlockRows), words, block);
            px.insert(px.end(), block.begin(), block.end());
        }
        part.film = Film::from_pixels(part.id.width, part.id.height, std::move(px));
    });
    return part;
}

PartialRender merge_partials(const std::vector<PartialRender>& parts, const std::vector<std::string>& names) {
    PartialRender out;
    const std::vector<size_t> order = plan_merge(parts, names, out);
    std::vector<FilmPixel> px = parts[order[0]].film.pixels();
    for (size_t k = 1; k < order.size(); ++k)
        add_pixels(px.data(), parts[order[k]].film.pixels().data(), px.size(), 0, out.id.width, names[order[k]]);
    out.film = Film::from_pixels(out.id.width, out.id.height, std::move(px));
    return out;
}

PartialRender merge_partial_files(const std::vector<std::string>& paths,
                                  const std::function<void(int, int)>& before_pixels) {
    // Every header first (identity, ranges, size for the file, the image budget): nothing is allocated for pixels
    // until every part is known to fit.
    std::vector<PartialRender> headers;
    for (const std::string& path : paths)
        guarded(path, [&](Imf::InputFile& file) { headers.push_back(read_header(path, file)); });
    PartialRender out;
    const std::vector<size_t> order = plan_merge(headers, paths, out);
    const int w = out.id.width, h = out.id.height;
    if (before_pixels) before_pixels(w, h);
    // The output film, then each part added block by block in order of its first sample index (as Film::merge).
    std::vector<FilmPixel> px;
    try {
        px.resize(size_t(w) * size_t(h));
    } catch (const std::bad_alloc&) {
        throw Error(paths[order[0]] + ": out of memory for the " + std::to_string(w) + "x" + std::to_string(h) +
                    " merged film (" + std::to_string(sizeof(FilmPixel)) + " bytes a pixel)");
    }
    std::vector<std::vector<uint32_t>> words;
    std::vector<FilmPixel> block;
    for (size_t k = 0; k < order.size(); ++k) {
        const std::string& path = paths[order[k]];
        guarded(path, [&](Imf::InputFile& file) {
            for (int y0 = 0; y0 < h; y0 += kBlockRows) {
                read_rows(path, file, headers[order[k]], y0, std::min(h, y0 + kBlockRows), words, block);
                FilmPixel* dst = px.data() + size_t(y0) * size_t(w);
                if (k == 0)
                    std::copy(block.begin(), block.end(), dst);
                else
                    add_pixels(dst, block.data(), block.size(), size_t(y0) * size_t(w), w, path);
            }
        });
    }
    out.film = Film::from_pixels(w, h, std::move(px));
    return out;
}

}  // namespace pv
