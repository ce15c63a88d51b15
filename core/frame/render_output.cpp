// core/frame/render_output.cpp: see render_output.h.
#include "core/frame/render_output.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "core/base/error.h"
#include "core/denoise/denoise_atrous.h"

namespace pv {

FeatureImage camera_features(const Renderer& renderer, const std::atomic<bool>* cancel) {
    const Film& film = renderer.film();
    return render_features(renderer.traceable(), renderer.camera(), film.width(), film.height(), 8,
                           renderer.settings().seed, cancel);
}

Image denoise_film(const Film& film, const FeatureImage& features, Denoiser denoiser, NforStats* stats,
                   const std::atomic<bool>* cancel) {
    if (denoiser == Denoiser::Nfor) return denoise_nfor(film, features, stats, cancel);
    const auto t0 = std::chrono::steady_clock::now();
    Image out = denoise_atrous(film.mean(), atrous_variance(film), features);
    if (stats) stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

double largest_rms(const Film& film) {
    double largest = 0.0;
    for (const FilmPixel& px : film.pixels())
        if (px.n)
            for (int c = 0; c < 3; ++c) largest = std::max(largest, px.sum_sq[c] / px.n);
    return std::sqrt(largest);
}

namespace {

// With aovs or denoise: the first-hit feature pass after the render (the render loop itself is unchanged), the
// denoised image and the feature layers. Refuses a film too bright for the float statistics.
void add_features(const OutputOptions& o, const Renderer& renderer, const Film& film, RenderOutput& out, Image& noisy) {
    const double rms = largest_rms(film);
    if (rms > kMaxDenoiseRms) {
        char msg[400];
        std::snprintf(msg, sizeof msg,
                      "%s: the brightest pixel's RMS radiance is %.3g, beyond the %.0e that the Variance layer and "
                      "the denoisers compute in float; scale the emission, --env-strength or --sun-irradiance down "
                      "(without %s the render is written as is)",
                      o.denoise ? "--denoise" : "--aovs", rms, kMaxDenoiseRms, o.denoise ? "--denoise" : "--aovs");
        throw Error(msg);
    }
    const auto aov_start = std::chrono::steady_clock::now();
    const FeatureImage features = camera_features(renderer);
    out.aov_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - aov_start).count();
    if (o.denoise) {
        noisy = out.image;
        out.image = denoise_film(film, features, o.denoiser, &out.nfor);
        out.metadata["pathview:denoiser"] = o.denoiser == Denoiser::Nfor ? "nfor" : "atrous";
        out.metadata["pathview:denoise_seconds"] = std::to_string(out.nfor.seconds);
    }
    if (o.aovs)
        for (ExrLayer& l : feature_layers(features)) out.layers.push_back(std::move(l));
}

}  // namespace

RenderOutput finish_render(const Renderer& renderer, const OutputOptions& o) {
    RenderOutput out;
    // The image as mixed with the light gains (the film itself, no copy, with every gain 1).
    Film mixed;
    if (!gains_identity(renderer.light_gains())) mixed = renderer.mixed_film();
    const Film& film = gains_identity(renderer.light_gains()) ? renderer.film() : mixed;
    out.image = film.mean();
    out.metadata = render_metadata(renderer);
    Image noisy;
    if (o.aovs || o.denoise) add_features(o, renderer, film, out, noisy);
    std::vector<Image> groups;
    const Film& raw = renderer.film();
    const LightGains& gains = renderer.light_gains();
    if (o.light_groups)
        for (int g = 0; g < raw.groups(); ++g) {
            groups.push_back(raw.group_mean(g));
            const vec3 k = size_t(g) < gains.size() ? gains[size_t(g)] : vec3(1.f);
            if (k != vec3(1.f))
                for (size_t i = 0; i < groups.back().rgb.size(); ++i) groups.back().rgb[i] *= k[int(i % 3)];
        }
    const auto expose = [&](Image& im) {
        for (float& v : im.rgb) {
            // Overflow saturates: a file never holds Inf (the film's means are finite and non-negative).
            const float s = v * std::exp2(o.exposure);
            v = std::isfinite(s) ? s : std::numeric_limits<float>::max();
        }
    };
    if (o.exposure != 0.f) {
        expose(out.image);
        expose(noisy);
        for (Image& im : groups) expose(im);
    }
    out.layers.insert(out.layers.begin(), rgb_layer(out.image));
    if (o.denoise) out.layers.push_back(rgb_layer(noisy, "noisy"));
    if (o.aovs)
        for (ExrLayer& l : film_layers(film)) out.layers.push_back(std::move(l));
    if (!groups.empty()) {
        const LightGroups& names = renderer.traceable().light_groups();
        std::string list, gain_text;
        for (size_t g = 0; g < groups.size(); ++g) {
            const std::string name = g < names.names.size() ? names.names[g] : "group" + std::to_string(g);
            out.layers.push_back(rgb_layer(groups[g], "LightGroup." + light_group_layer_name(name)));
            const vec3 k = g < gains.size() ? gains[g] : vec3(1.f);
            char buf[128];
            std::snprintf(buf, sizeof buf, "%s=%.9g,%.9g,%.9g", name.c_str(), double(k.x), double(k.y), double(k.z));
            list += (list.empty() ? "" : ";") + name;
            gain_text += (gain_text.empty() ? "" : ";") + std::string(buf);
        }
        out.metadata["pathview:light_groups"] = list;
        out.metadata["pathview:light_gains"] = gain_text;
    }
    return out;
}

std::string light_group_layer_name(const std::string& name) {
    std::string s = name.empty() ? "unnamed" : name;
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
    return s;
}

LightGains parse_light_gains(const std::vector<std::string>& specs, const std::vector<std::string>& names,
                             const std::string& what) {
    LightGains gains(names.size(), vec3(1.f));
    for (const std::string& spec : specs) {
        const size_t eq = spec.rfind('=');
        const std::string name = eq == std::string::npos ? "" : spec.substr(0, eq);
        if (eq == std::string::npos || name.empty())
            throw Error(what + " '" + spec + "': expected NAME=r,g,b or NAME=k (a light group's name and its gain)");
        const auto it = std::find(names.begin(), names.end(), name);
        if (it == names.end()) {
            std::string list;
            for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
            throw Error(what + " '" + spec + "': no light group '" + name +
                        "'; the scene's groups are: " + (list.empty() ? "(none)" : list));
        }
        std::vector<float> v;
        const std::string text = spec.substr(eq + 1);
        size_t start = 0;
        for (;;) {
            const size_t comma = text.find(',', start);
            const std::string part = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
            char* end = nullptr;
            const float x = std::strtof(part.c_str(), &end);
            if (part.empty() || end != part.c_str() + part.size() || !std::isfinite(x) || x < 0.f)
                throw Error(what + " '" + spec + "': the gain must be one or three finite numbers >= 0");
            v.push_back(x);
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        if (v.size() != 1 && v.size() != 3)
            throw Error(what + " '" + spec + "': the gain must be one or three finite numbers >= 0");
        gains[size_t(it - names.begin())] = v.size() == 1 ? vec3(v[0]) : vec3(v[0], v[1], v[2]);
    }
    return gains;
}

}  // namespace pv
