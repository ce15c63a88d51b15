// core/denoise/aov.cpp: the first-hit feature pass, the film's statistics as layers, and the multi-layer EXR writer.
#include "core/denoise/aov.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <unistd.h>

#include <filesystem>

#include "core/base/error.h"
#include "core/base/parallel.h"
#include "core/image/exr_io.h"
#include "core/render/shading.h"

namespace pv {
namespace {

constexpr int kMaxSpecularChain = 16;

// The colour a denoiser should see: what the surface reflects at normal incidence, roughly its albedo.
vec3 base_color(const Bsdf& bsdf) {
    if (const auto* l = std::get_if<Lambertian>(&bsdf)) return l->albedo;
    if (const auto* g = std::get_if<Glossy>(&bsdf)) return glm::min(g->diffuse + g->specular, vec3(1.f));
    if (const auto* m = std::get_if<Mirror>(&bsdf)) return m->reflectance;
    if (const auto* m = std::get_if<MetallicRoughness>(&bsdf)) return m->base_color;  // glTF's base colour
    return vec3(1.f);
}

}  // namespace

FeatureSample trace_features(const TraceableScene& ts, Ray ray, Sampler& sampler) {
    const Scene& scene = ts.scene();
    FeatureSample out;
    vec3 tint(1.f);
    float travelled = 0.f;
    for (int bounce = 0; bounce < kMaxSpecularChain; ++bounce) {
        Hit hit;
        if (!ts.intersect(ray, hit)) return FeatureSample{};
        // The surface as the integrator shades it (core/render/shading.h): the normal map's normal, the BSDF with its
        // base-colour texture, vertex colours and metallic-roughness texture.
        SurfacePoint sf = surface_point(scene, hit);
        travelled += glm::length(sf.p - ray.o);
        const Material& mat = ts.material(hit.prim);
        apply_normal_map(scene, mat, hit, scene.uv_at(hit.prim, hit.u, hit.v), -ray.d, sf);
        const Bsdf bsdf = hit_bsdf(mat, hit_textures(scene, mat, hit));
        const bool front = glm::dot(ray.d, sf.ng) < 0.f;
        vec3 ns = sf.ns;
        if (glm::dot(ray.d, ns) > 0.f) ns = -ns;  // facing the arriving ray
        if (!is_delta(bsdf) || mat.has_emission()) {
            // An emitter's albedo is its emission clamped to 1: a lamp's diffuser is often the colour of the ceiling
            // around it, and a denoiser must not blend the two.
            const vec3 albedo = mat.has_emission() ? glm::min(mat.emission, vec3(1.f)) : base_color(bsdf);
            out.albedo = tint * albedo;
            out.normal = ns;
            out.depth = travelled;
            return out;
        }
        // A delta surface: continue along its (chosen) specular direction, in the integrator's frame convention.
        const bool is_glass = oriented_eta(bsdf) != 0.f;
        const vec3 ng = (is_glass || front) ? sf.ng : -sf.ng;
        const vec3 frame_n = (is_glass || front) ? sf.ns : -sf.ns;
        const Frame frame((glm::dot(-ray.d, frame_n) > 0.f) == (glm::dot(-ray.d, ng) > 0.f) ? frame_n : ng);
        const auto bs = sample(bsdf, frame.to_local(-ray.d), sampler.get1d(), vec2(0.5f));
        if (!bs) return FeatureSample{};
        if (const auto* m = std::get_if<Mirror>(&bsdf)) tint *= m->reflectance;  // glass: untinted
        if (std::holds_alternative<MetallicRoughness>(bsdf))  // its lobe's weight (base colour, Fresnel)
            tint *= glm::min(bs->f * (std::fabs(bs->wi.z) / bs->pdf), vec3(1.f));
        const vec3 wi = frame.to_world(bs->wi);
        ray.o = offset_ray_origin(sf.p, glm::dot(wi, sf.ng) > 0.f ? sf.ng : -sf.ng, sf.p_error);
        ray.d = wi;
        ray.tmax = std::numeric_limits<float>::infinity();
    }
    return out;
}

FeatureImage render_features(const TraceableScene& ts, const Camera& camera, int width, int height, int samples,
                             uint32_t seed, const std::atomic<bool>* cancel) {
    FeatureImage img;
    img.width = width;
    img.height = height;
    const size_t n = size_t(width) * size_t(height);
    img.albedo.assign(n, vec3(0.f));
    img.normal.assign(n, vec3(0.f));
    img.depth.assign(n, 0.f);
    const float inv = 1.f / float(std::max(samples, 1));
    parallel_for_range(0, height, [&](const tbb::blocked_range<int>& rows) {
        enable_ftz_daz();
        // Independent of the render's samples: a sampler of its own seed.
        Sampler sampler(seed ^ 0x41f0u, SamplerKind::Independent);
        for (int y = rows.begin(); y != rows.end(); ++y) {
            if (cancel && cancel->load(std::memory_order_relaxed)) return;
            for (int x = 0; x < width; ++x) {
                FeatureSample acc;
                for (int s = 0; s < samples; ++s) {
                    const Ray ray = camera_ray(camera, sampler, x, y, uint32_t(s));
                    const FeatureSample f = trace_features(ts, ray, sampler);
                    acc.albedo += f.albedo;
                    acc.normal += f.normal;
                    acc.depth += f.depth;
                }
                const size_t i = size_t(y) * size_t(width) + size_t(x);
                img.albedo[i] = acc.albedo * inv;
                img.normal[i] = acc.normal * inv;  // averaged: shorter than 1 across an edge, as denoisers expect
                img.depth[i] = acc.depth * inv;
            }
        }
    });
    return img;
}

std::vector<ExrLayer> film_layers(const Film& film) {
    const size_t n = size_t(film.width()) * size_t(film.height());
    ExrLayer count{{"SampleCount"}, std::vector<float>(n)};
    ExrLayer var{{"Variance.R", "Variance.G", "Variance.B"}, film.variance_of_mean().rgb};
    ExrLayer even{{"even.R", "even.G", "even.B"}, std::vector<float>(n * 3)};
    ExrLayer odd{{"odd.R", "odd.G", "odd.B"}, std::vector<float>(n * 3)};
    for (int y = 0, i = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x, ++i) {
            const FilmPixel& px = film.pixel(x, y);
            count.data[size_t(i)] = float(px.n);
            for (int c = 0; c < 3; ++c) {
                even.data[size_t(i) * 3 + size_t(c)] = px.n_even ? float(px.even_mean(c)) : 0.f;
                odd.data[size_t(i) * 3 + size_t(c)] = px.n_odd() ? float(px.odd_mean(c)) : 0.f;
            }
        }
    return {std::move(count), std::move(var), std::move(even), std::move(odd)};
}

std::vector<ExrLayer> feature_layers(const FeatureImage& f) {
    const size_t n = f.albedo.size();
    ExrLayer albedo{{"Albedo.R", "Albedo.G", "Albedo.B"}, std::vector<float>(n * 3)};
    ExrLayer normal{{"Ns.X", "Ns.Y", "Ns.Z"}, std::vector<float>(n * 3)};
    ExrLayer depth{{"Z"}, f.depth};
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            albedo.data[i * 3 + size_t(c)] = f.albedo[i][c];
            normal.data[i * 3 + size_t(c)] = f.normal[i][c];
        }
    return {std::move(albedo), std::move(normal), std::move(depth)};
}

ExrLayer rgb_layer(const Image& image, const std::string& prefix) {
    const std::string p = prefix.empty() ? "" : prefix + ".";
    return ExrLayer{{p + "R", p + "G", p + "B"}, image.rgb};
}

void write_exr_layers(const std::string& path, int width, int height, const std::vector<ExrLayer>& layers,
                      const Metadata& metadata) {
    const size_t n = size_t(width) * size_t(height);
    for (const ExrLayer& l : layers)
        if (l.channels.empty() || l.data.size() != n * l.channels.size())
            throw Error(path + ": cannot write EXR: layer " + (l.channels.empty() ? "?" : l.channels[0]) +
                        " does not match the image size " + std::to_string(width) + "x" + std::to_string(height));
    Imf::Header header(width, height);
    for (const ExrLayer& l : layers)
        for (const std::string& c : l.channels) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    for (const auto& [k, v] : metadata) header.insert(k, Imf::StringAttribute(v));
    write_exr_atomically(path, header, [&](Imf::OutputFile& file) {
        Imf::FrameBuffer fb;
        for (const ExrLayer& l : layers) {
            const size_t xs = l.channels.size() * sizeof(float), ys = xs * size_t(width);
            char* base = reinterpret_cast<char*>(const_cast<float*>(l.data.data()));
            for (size_t c = 0; c < l.channels.size(); ++c)
                fb.insert(l.channels[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
        }
        file.setFrameBuffer(fb);
        file.writePixels(height);
    });
}

ExrLayer read_exr_layer(const std::string& path, const std::vector<std::string>& channels, int* width, int* height) {
    ExrLayer l;
    try {
        read_exr_guarded(path, [&](Imf::InputFile& file) {
            const Imath::Box2i dw = file.header().dataWindow();
            const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
            if (w <= 0 || h <= 0 || w * h > (1l << 28)) throw Error(path + ": EXR data window is empty or too large");
            l = ExrLayer{channels, std::vector<float>(size_t(w) * size_t(h) * channels.size())};
            Imf::FrameBuffer fb;
            const size_t xs = channels.size() * sizeof(float), ys = xs * size_t(w);
            char* base = reinterpret_cast<char*>(l.data.data()) - (size_t(dw.min.x) * xs + size_t(dw.min.y) * ys);
            for (size_t c = 0; c < channels.size(); ++c) {
                if (!file.header().channels().findChannel(channels[c]))
                    throw Error(path + ": EXR has no channel " + channels[c]);
                fb.insert(channels[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
            }
            file.setFrameBuffer(fb);
            file.readPixels(dw.min.y, dw.max.y);
            if (width) *width = int(w);
            if (height) *height = int(h);
        });
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read EXR: " + e.what());
    }
    return l;
}

}  // namespace pv
