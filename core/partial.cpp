// core/partial.cpp: the partial-render EXR (OpenEXR UINT channels for the exact double sums), its validation,
// the scene identity hash and the merge.
#include "core/partial.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <sstream>
#include <type_traits>
#include <variant>

#include "core/error.h"
#include "core/exr_io.h"
#include "core/renderer.h"
#include "core/rng.h"
#include "core/version.h"

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

// Word-at-a-time content hash (SplitMix64 mixing of each 8-byte word, core/rng.h).
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
    if (m.emissive_texture != kNoIndex || !m.emissive_uv.is_identity()) {  // glTF only: OBJ hashes as before
        h.value(m.emissive_texture);
        h.value(m.emissive_uv.col0);
        h.value(m.emissive_uv.col1);
        h.value(m.emissive_uv.offset);
        h.value(m.emissive_uv.set);
    }
}

uint64_t parse_u64(const std::string& s, bool& ok) {
    char* end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
    ok = !s.empty() && end && *end == '\0' && errno == 0 && s[0] != '-';
    return v;
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
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        const size_t colon = item.find(':');
        bool ok_a = false, ok_b = false;
        const uint64_t a = colon == std::string::npos ? 0 : parse_u64(item.substr(0, colon), ok_a);
        const uint64_t b = colon == std::string::npos ? 0 : parse_u64(item.substr(colon + 1), ok_b);
        if (!ok_a || !ok_b || b == 0 || a + b > (uint64_t(1) << 32))
            throw Error(what + ": sample range '" + item +
                        "'; expected START:COUNT with COUNT > 0 and "
                        "START + COUNT <= 2^32");
        out.push_back({uint32_t(a), uint32_t(b)});
    }
    if (out.empty()) throw Error(what + ": no sample range; expected START:COUNT[,START:COUNT...]");
    normalize_ranges(out, what);
    return out;
}

SampleRange shard_range(uint32_t index, uint32_t shards, uint32_t total) {
    if (shards == 0 || index >= shards)
        throw Error("--shard " + std::to_string(index) + "/" + std::to_string(shards) +
                    ": expected INDEX/COUNT with 0 <= INDEX < COUNT");
    if (total < shards)
        throw Error("--shard " + std::to_string(index) + "/" + std::to_string(shards) + ": " + std::to_string(total) +
                    " samples cannot fill " + std::to_string(shards) + " shards; use at most " + std::to_string(total) +
                    " shards");
    const uint32_t base = total / shards, extra = total % shards;
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
        throw Error(what + ": camera '" + text +
                    "' is malformed; expected --eye x,y,z --target x,y,z --up x,y,z "
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
        else if (key == "sampler" && parse_sampler(value))
            s.sampler = *parse_sampler(value);
        else
            ok = false;
    }
    if (!ok || s.describe() != text)
        throw Error(what + ": settings '" + text + "' are not understood by " + partial_version());
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

void write_partial(const std::string& path, const PartialRender& part) {
    const Film& film = part.film;
    const int w = film.width(), h = film.height();
    const size_t n = size_t(w) * size_t(h);
    const std::vector<FilmPixel>& px = film.pixels();

    // Planes: the mean as FLOAT, each double as its high and low 32-bit words, the counts.
    const Image mean = film.mean();
    std::vector<std::vector<uint32_t>> words;
    std::vector<std::string> names;
    for (const Plane& plane : kPlanes)
        for (int c = 0; c < 3; ++c) {
            std::vector<uint32_t> hi(n), lo(n);
            for (size_t i = 0; i < n; ++i) {
                uint64_t bits;
                std::memcpy(&bits, &(px[i].*plane.field)[c], 8);
                hi[i] = uint32_t(bits >> 32);
                lo[i] = uint32_t(bits);
            }
            names.push_back(std::string(plane.layer) + "_hi." + kRgb[c]);
            words.push_back(std::move(hi));
            names.push_back(std::string(plane.layer) + "_lo." + kRgb[c]);
            words.push_back(std::move(lo));
        }
    for (const CountPlane& cp : kCounts) {
        std::vector<uint32_t> v(n);
        for (size_t i = 0; i < n; ++i) v[i] = px[i].*cp.field;
        names.push_back(cp.name);
        words.push_back(std::move(v));
    }

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
        Imf::FrameBuffer fb;
        char* rgb = reinterpret_cast<char*>(const_cast<float*>(mean.rgb.data()));
        for (int c = 0; c < 3; ++c)
            fb.insert(kRgb[c], Imf::Slice(Imf::FLOAT, rgb + c * sizeof(float), 3 * sizeof(float),
                                          3 * sizeof(float) * size_t(w)));
        for (size_t k = 0; k < names.size(); ++k)
            fb.insert(names[k], Imf::Slice(Imf::UINT, reinterpret_cast<char*>(words[k].data()), sizeof(uint32_t),
                                           sizeof(uint32_t) * size_t(w)));
        file.setFrameBuffer(fb);
        file.writePixels(h);
    });
}

PartialRender read_partial(const std::string& path) {
    PartialRender part;
    try {
        read_exr_guarded(
            path,
            [&](Imf::InputFile& file) {
                const Imf::Header& header = file.header();
                Metadata attrs;
                for (auto it = header.begin(); it != header.end(); ++it)
                    if (auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                        attrs[it.name()] = s->value();
                auto attr = [&](const char* key) {
                    const auto it = attrs.find(key);
                    if (it == attrs.end())
                        throw Error(path + ": attribute " + key + " is missing; the file is damaged");
                    return it->second;
                };
                if (!attrs.count("pathview:partial"))
                    throw Error(path +
                                ": not a partial render (no pathview:partial attribute); expected a file written by "
                                "`pathview render --samples`, `--resume` or `pathview merge`");
                if (attrs["pathview:partial"] != kFormat || attr("pathview:version") != partial_version())
                    throw Error(path + ": written by " + attrs["pathview:version"] + " (format " +
                                attrs["pathview:partial"] + "); this is " + partial_version() +
                                ", which reads only its own partial renders");

                const Imath::Box2i dw = header.dataWindow();
                const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
                if (dw.min.x != 0 || dw.min.y != 0 || w <= 0 || h <= 0 || w * h > (1l << 28))
                    throw Error(path + ": data window is not [0, w) x [0, h) or is too large");
                part.id.version = attrs["pathview:version"];
                const std::string hash = attr("pathview:scene_hash");
                part.id.scene_hash = std::strtoull(hash.c_str(), nullptr, 16);
                if (hash.size() != 16 || hash.find_first_not_of("0123456789abcdef") != std::string::npos)
                    throw Error(path + ": pathview:scene_hash '" + hash + "' is not 16 hex digits");
                part.id.settings = attr("pathview:settings");
                parse_settings(part.id.settings, path);
                part.id.camera = attr("pathview:partial:camera");
                parse_camera(part.id.camera, path);
                part.id.width = int(w);
                part.id.height = int(h);
                part.ranges = parse_ranges(attr("pathview:samples"), path);
                for (const auto& [k, v] : attrs)
                    if (!kReservedKeys.count(k)) part.info[k] = v;

                // Every channel, as UINT words.
                const size_t n = size_t(w) * size_t(h);
                std::vector<std::string> names;
                for (const Plane& plane : kPlanes)
                    for (int c = 0; c < 3; ++c)
                        for (const char* half : {"_hi.", "_lo."})
                            names.push_back(std::string(plane.layer) + half + kRgb[c]);
                for (const CountPlane& cp : kCounts) names.push_back(cp.name);
                std::vector<std::vector<uint32_t>> words(names.size(), std::vector<uint32_t>(n));
                Imf::FrameBuffer fb;
                for (size_t k = 0; k < names.size(); ++k) {
                    const Imf::Channel* ch = header.channels().findChannel(names[k]);
                    if (!ch || ch->type != Imf::UINT)
                        throw Error(path + ": channel " + names[k] + " is missing or not UINT");
                    fb.insert(names[k], Imf::Slice(Imf::UINT, reinterpret_cast<char*>(words[k].data()),
                                                   sizeof(uint32_t), sizeof(uint32_t) * size_t(w)));
                }
                file.setFrameBuffer(fb);
                file.readPixels(dw.min.y, dw.max.y);
                if (!file.isComplete()) throw Error(path + ": the file is truncated");

                std::vector<FilmPixel> px(n);
                size_t k = 0;
                for (const Plane& plane : kPlanes)
                    for (int c = 0; c < 3; ++c, k += 2)
                        for (size_t i = 0; i < n; ++i) {
                            const uint64_t bits = (uint64_t(words[k][i]) << 32) | words[k + 1][i];
                            double v;
                            std::memcpy(&v, &bits, 8);
                            if (!(std::isfinite(v) && v >= 0.0))
                                throw Error(path + ": pixel (" + std::to_string(i % size_t(w)) + ", " +
                                            std::to_string(i / size_t(w)) + ") has a " + plane.layer +
                                            " that is negative or not finite; the file is damaged");
                            (px[i].*plane.field)[c] = v;
                        }
                for (const CountPlane& cp : kCounts) {
                    for (size_t i = 0; i < n; ++i) px[i].*cp.field = words[k][i];
                    ++k;
                }
                const uint64_t total = part.sample_count();
                for (size_t i = 0; i < n; ++i)
                    if (px[i].n > total || px[i].n_even > px[i].n)
                        throw Error(
                            path + ": pixel (" + std::to_string(i % size_t(w)) + ", " + std::to_string(i / size_t(w)) +
                            ") counts " + std::to_string(px[i].n) + " samples (" + std::to_string(px[i].n_even) +
                            " in the first half), more than its " + std::to_string(total) + "; the file is damaged");
                part.film = Film::from_pixels(int(w), int(h), std::move(px));
            },
            "a partial render EXR");
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read EXR: " + one_line(e.what()));
    }
    return part;
}

PartialRender merge_partials(const std::vector<PartialRender>& parts, const std::vector<std::string>& names) {
    if (parts.empty()) throw Error("merge: no partial renders given");
    // Add in order of the first sample index, so the result does not depend on the order of the arguments.
    std::vector<size_t> order(parts.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return parts[a].ranges.front().start < parts[b].ranges.front().start; });

    const PartialRender& first = parts[order[0]];
    const std::string& first_name = names[order[0]];
    PartialRender out = first;
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
            throw Error(name + ": " + what + " '" + mine + "' differs from " + first_name + "'s '" + theirs +
                        "'; parts of one render must agree");
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

    for (size_t k = 1; k < order.size(); ++k) {
        out.film.merge(parts[order[k]].film);
        add_summed_info(out.info, parts[order[k]].info);
    }
    out.ranges.clear();
    for (const Owned& o : all) out.ranges.push_back(o.range);
    normalize_ranges(out.ranges, "merge");
    return out;
}

}  // namespace pv
