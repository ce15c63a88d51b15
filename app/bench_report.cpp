// app/bench_report.cpp: configuration names and the table, equal-time summary, CSV and SVG writers of
// `pathview bench`.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string_view>
#include <type_traits>

#include "app/bench.h"
#include "core/base/error.h"
#include "core/base/file_io.h"

namespace pv::app {
namespace {

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : s) {
        if (c == sep) {
            out.push_back(cur);
            cur.clear();
        } else if (c != ' ') {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

// Writes `text` whole (core/base/file_io.h: a temporary file, checked writes, fsync, rename).
void write_file(const std::string& path, const std::string& text) {
    write_file_atomically(path, [&](int fd) { write_all(fd, text.data(), text.size(), path); });
}

// The words a configuration uses for the settings-table field `key` of type T: each value once, by its shortest
// word in the table (sampler: ind|sobol; light_sampler: power|tree).
template <class T>
std::vector<NamedValue<T>> short_words(const char* key) {
    std::vector<NamedValue<T>> out;
    for_each_setting([&](const auto& f) {
        if constexpr (std::is_same_v<std::decay_t<decltype(RenderSettings{}.*f.member)>, T>) {
            if (std::string_view(f.key) != key) return;
            for (size_t i = 0; i < f.name_count; ++i) {
                const NamedValue<T>& w = f.names[i];
                auto same =
                    std::find_if(out.begin(), out.end(), [&](const NamedValue<T>& o) { return o.value == w.value; });
                if (same == out.end())
                    out.push_back(w);
                else if (std::strlen(w.name) < std::strlen(same->name))
                    *same = w;
            }
        }
    });
    return out;
}

template <class T>
std::string joined(const std::vector<NamedValue<T>>& words) {
    std::string out;
    for (const NamedValue<T>& w : words) out += (out.empty() ? "" : "|") + std::string(w.name);
    return out;
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

}  // namespace

std::vector<BenchConfig> parse_configs(const std::string& list, const RenderSettings& base) {
    // The estimator (nee and mis) and roulette words are bench's own; the samplers' come from the settings table.
    const char* estimators[] = {"bsdf", "nee", "mis"};
    const char* rrs[] = {"rr", "norr"};
    const std::vector<NamedValue<SamplerKind>> samplers = short_words<SamplerKind>("sampler");
    const std::vector<NamedValue<LightSamplerKind>> light_samplers = short_words<LightSamplerKind>("light_sampler");
    std::vector<BenchConfig> out;
    for (std::string item : split(list, ',')) {
        if (item.empty()) continue;
        if (item == "all") item = "*/*/*";
        const std::vector<std::string> f = split(item, '/');
        auto bad = [&] {
            return Error("--configs " + item +
                         ": expected estimator/rr/sampler[/light-sampler] with estimator bsdf|nee|mis, rr rr|norr, "
                         "sampler " +
                         joined(samplers) + ", light sampler " + joined(light_samplers) +
                         " (each may be *), e.g. mis/rr/sobol, mis/rr/sobol/tree, or all");
        };
        if (f.size() != 3 && f.size() != 4) throw bad();
        // Without the fourth field, --light-sampler's choice and the names of before.
        const bool with_light = f.size() == 4;
        bool matched = false;
        for (const char* e : estimators)
            for (const char* r : rrs)
                for (const NamedValue<SamplerKind>& s : samplers)
                    for (const NamedValue<LightSamplerKind>& l : light_samplers) {
                        if ((f[0] != "*" && f[0] != e) || (f[1] != "*" && f[1] != r) || (f[2] != "*" && f[2] != s.name))
                            continue;
                        if (with_light ? f[3] != "*" && f[3] != l.name : l.value != base.light_sampler) continue;
                        matched = true;
                        BenchConfig c;
                        c.name =
                            std::string(e) + "/" + r + "/" + s.name + (with_light ? std::string("/") + l.name : "");
                        c.settings = base;
                        c.settings.light_sampling = std::string(e) != "bsdf";
                        c.settings.mis = std::string(e) == "mis";
                        c.settings.russian_roulette = std::string(r) == "rr";
                        c.settings.sampler = s.value;
                        c.settings.light_sampler = l.value;
                        const bool dup =
                            std::any_of(out.begin(), out.end(), [&](const BenchConfig& o) { return o.name == c.name; });
                        if (!dup) out.push_back(c);
                    }
        if (!matched) throw bad();
    }
    if (out.empty()) throw Error("--configs: no configuration given");
    return out;
}

void print_points_table(const std::vector<BenchSeries>& series) {
    std::printf(
        "| config | spp | seconds | relMSE (mean) | relMSE min..max over seeds | trimmed relMSE | RMSE | MAPE | "
        "Mrays/s | path length | rays/sample | efficiency 1/(relMSE s) |\n");
    std::printf("|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const BenchSeries& s : series)
        for (const BenchPoint& p : s.points)
            std::printf("| %s | %u | %.3f | %.4g | %.3g..%.3g | %.4g | %.4g | %.4g | %.2f | %.2f | %.2f | %.4g |\n",
                        s.config.name.c_str(), p.spp, p.seconds.mean, p.rel_mse.mean, p.rel_mse.min, p.rel_mse.max,
                        p.rel_mse_trimmed.mean, p.rmse.mean, p.mape.mean, p.mrays_per_s, p.mean_path_length,
                        p.rays_per_sample, p.efficiency());
}

void print_denoise_table(const std::vector<BenchSeries>& series) {
    std::printf(
        "| config | spp | noisy relMSE | a-trous relMSE | a-trous ms | NFOR relMSE | NFOR s |\n"
        "|---|---:|---:|---:|---:|---:|---:|\n");
    for (const BenchSeries& s : series)
        for (const BenchPoint& p : s.points)
            if (p.denoised)
                std::printf("| %s | %u | %.4g | %.4g | %.1f | %.4g | %.2f |\n", s.config.name.c_str(), p.spp,
                            p.rel_mse.mean, p.rel_mse_atrous.mean, p.atrous_seconds.mean * 1e3, p.rel_mse_nfor.mean,
                            p.nfor_seconds.mean);
}

void write_csv(const std::string& path, const std::string& scene, const std::vector<BenchSeries>& series) {
    std::ostringstream o;
    // A column per field of the settings table (core/render/settings.h), named by its key, valued by its word.
    o << "scene,config";
    for_each_setting([&](const auto& f) { o << ',' << f.key; });
    o << ",spp,seeds,seconds_mean,seconds_std,relmse_mean,relmse_std,relmse_min,relmse_max,relmse_trimmed_mean,"
         "rmse_mean,mape_mean,mrays_per_s,mean_path_length,rays_per_sample,efficiency,relmse_atrous_mean,"
         "atrous_seconds_mean,relmse_nfor_mean,nfor_seconds_mean\n";
    for (const BenchSeries& s : series)
        for (const BenchPoint& p : s.points) {
            o << '"' << scene << "\"," << s.config.name;
            for_each_setting([&](const auto& f) { o << ',' << f.word(s.config.settings.*f.member); });
            o << ',' << p.spp << ',' << p.seeds << ',' << fmt("%.6g", p.seconds.mean) << ','
              << fmt("%.3g", p.seconds.stddev) << ',' << fmt("%.6g", p.rel_mse.mean) << ','
              << fmt("%.4g", p.rel_mse.stddev) << ',' << fmt("%.6g", p.rel_mse.min) << ',' << fmt("%.6g", p.rel_mse.max)
              << ',' << fmt("%.6g", p.rel_mse_trimmed.mean) << ',' << fmt("%.6g", p.rmse.mean) << ','
              << fmt("%.6g", p.mape.mean) << ',' << fmt("%.4g", p.mrays_per_s) << ',' << fmt("%.4g", p.mean_path_length)
              << ',' << fmt("%.4g", p.rays_per_sample) << ',' << fmt("%.6g", p.efficiency());
            // Denoised columns: empty unless bench --denoise measured them.
            if (p.denoised)
                o << ',' << fmt("%.6g", p.rel_mse_atrous.mean) << ',' << fmt("%.4g", p.atrous_seconds.mean) << ','
                  << fmt("%.6g", p.rel_mse_nfor.mean) << ',' << fmt("%.4g", p.nfor_seconds.mean);
            else
                o << ",,,,";
            o << '\n';
        }
    write_file(path, o.str());
}

namespace {

// A log-log panel: maps data to pixels and draws decade grid lines and labels.
struct Panel {
    double x0, y0, w, h;                    // pixel rectangle
    double lx_min, lx_max, ly_min, ly_max;  // log10 data range
    double px(double x) const { return x0 + (std::log10(x) - lx_min) / (lx_max - lx_min) * w; }
    double py(double y) const { return y0 + h - (std::log10(y) - ly_min) / (ly_max - ly_min) * h; }
};

void draw_axes(std::ostringstream& o, const Panel& p, const char* xlabel, const char* title) {
    o << "<rect x='" << p.x0 << "' y='" << p.y0 << "' width='" << p.w << "' height='" << p.h
      << "' fill='white' stroke='#333'/>\n";
    for (int d = int(std::floor(p.lx_min)); d <= int(std::ceil(p.lx_max)); ++d) {
        if (d < p.lx_min - 1e-9 || d > p.lx_max + 1e-9) continue;
        const double x = p.px(std::pow(10.0, d));
        o << "<line x1='" << x << "' y1='" << p.y0 << "' x2='" << x << "' y2='" << p.y0 + p.h
          << "' stroke='#ddd'/>\n<text x='" << x << "' y='" << p.y0 + p.h + 16
          << "' font-size='11' text-anchor='middle'>1e" << d << "</text>\n";
    }
    for (int d = int(std::floor(p.ly_min)); d <= int(std::ceil(p.ly_max)); ++d) {
        if (d < p.ly_min - 1e-9 || d > p.ly_max + 1e-9) continue;
        const double y = p.py(std::pow(10.0, d));
        o << "<line x1='" << p.x0 << "' y1='" << y << "' x2='" << p.x0 + p.w << "' y2='" << y
          << "' stroke='#ddd'/>\n<text x='" << p.x0 - 6 << "' y='" << y + 4 << "' font-size='11' text-anchor='end'>1e"
          << d << "</text>\n";
    }
    o << "<text x='" << p.x0 + p.w / 2 << "' y='" << p.y0 + p.h + 34 << "' font-size='12' text-anchor='middle'>"
      << xlabel << "</text>\n<text x='" << p.x0 + p.w / 2 << "' y='" << p.y0 - 8
      << "' font-size='13' text-anchor='middle'>" << title << "</text>\n";
}

}  // namespace

void write_svg(const std::string& path, const std::string& title, const std::vector<BenchSeries>& series) {
    // Colours by estimator and roulette; line style by sampler (solid Sobol, dashed independent).
    auto colour = [](const RenderSettings& s) {
        const int e = !s.light_sampling ? 0 : (s.mis ? 2 : 1);
        static const char* on[] = {"#1f77b4", "#2ca02c", "#d62728"};
        static const char* off[] = {"#7fb2e0", "#98df8a", "#ff9896"};
        return s.russian_roulette ? on[e] : off[e];
    };
    double t_lo = 1e300, t_hi = 0, s_lo = 1e300, s_hi = 0, e_lo = 1e300, e_hi = 0;
    for (const BenchSeries& s : series)
        for (const BenchPoint& p : s.points) {
            if (!(p.rel_mse.mean > 0) || !(p.seconds.mean > 0)) continue;
            t_lo = std::min(t_lo, p.seconds.mean), t_hi = std::max(t_hi, p.seconds.mean);
            s_lo = std::min(s_lo, double(p.spp)), s_hi = std::max(s_hi, double(p.spp));
            e_lo = std::min(e_lo, std::max(p.rel_mse.min, 1e-12)), e_hi = std::max(e_hi, p.rel_mse.max);
        }
    if (t_hi == 0) t_lo = 1e-3, t_hi = 1, s_lo = 1, s_hi = 2, e_lo = 1e-3, e_hi = 1;
    const double W = 1180, H = 520;
    Panel left{70,
               50,
               420,
               380,
               std::floor(std::log10(t_lo)),
               std::ceil(std::log10(t_hi)),
               std::floor(std::log10(e_lo)),
               std::ceil(std::log10(e_hi))};
    Panel right = left;
    right.x0 = 560;
    right.lx_min = std::floor(std::log10(s_lo));
    right.lx_max = std::ceil(std::log10(s_hi));
    if (right.lx_max == right.lx_min) right.lx_max += 1;
    if (left.lx_max == left.lx_min) left.lx_max += 1;
    if (left.ly_max == left.ly_min) left.ly_max += 1, right.ly_max = left.ly_max;

    std::ostringstream o;
    o << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H << "' font-family='sans-serif'>\n"
      << "<rect width='100%' height='100%' fill='#fafafa'/>\n<text x='" << W / 2
      << "' y='22' font-size='15' text-anchor='middle'>" << title << "</text>\n";
    draw_axes(o, left, "render time (s, log)", "relMSE vs time");
    draw_axes(o, right, "samples per pixel (log)", "relMSE vs spp");
    // Slope -1 guides through the middle of each panel's data, clipped to the panel.
    for (const Panel* p : {&left, &right}) {
        const double lx_mid = 0.5 * (p->lx_min + p->lx_max), ly_mid = 0.5 * (p->ly_min + p->ly_max);
        const double a = std::max(p->lx_min, lx_mid - (p->ly_max - ly_mid)),
                     b = std::min(p->lx_max, lx_mid + (ly_mid - p->ly_min));
        o << "<line x1='" << p->px(std::pow(10, a)) << "' y1='" << p->py(std::pow(10, ly_mid - (a - lx_mid)))
          << "' x2='" << p->px(std::pow(10, b)) << "' y2='" << p->py(std::pow(10, ly_mid - (b - lx_mid)))
          << "' stroke='#888' stroke-width='1.5' stroke-dasharray='2,4'/>\n<text x='" << p->px(std::pow(10, b)) - 4
          << "' y='" << p->py(std::pow(10, ly_mid - (b - lx_mid))) - 6
          << "' font-size='11' fill='#666' text-anchor='end'>slope -1</text>\n";
    }
    for (const BenchSeries& s : series) {
        const char* c = colour(s.config.settings);
        const bool sobol = s.config.settings.sampler == SamplerKind::Sobol;
        for (int panel = 0; panel < 2; ++panel) {
            const Panel& p = panel == 0 ? left : right;
            std::ostringstream line;
            for (const BenchPoint& pt : s.points) {
                if (!(pt.rel_mse.mean > 0) || !(pt.seconds.mean > 0)) continue;
                const double x = p.px(panel == 0 ? pt.seconds.mean : double(pt.spp));
                line << x << ',' << p.py(pt.rel_mse.mean) << ' ';
                o << "<line x1='" << x << "' y1='" << p.py(std::max(pt.rel_mse.min, 1e-12)) << "' x2='" << x << "' y2='"
                  << p.py(pt.rel_mse.max) << "' stroke='" << c << "' stroke-width='1' opacity='0.6'/>\n";
            }
            o << "<polyline fill='none' stroke='" << c << "' stroke-width='2'"
              << (sobol ? "" : " stroke-dasharray='6,4'") << " points='" << line.str() << "'/>\n";
        }
    }
    // Legend.
    double ly = 60;
    for (const BenchSeries& s : series) {
        const bool sobol = s.config.settings.sampler == SamplerKind::Sobol;
        o << "<line x1='1000' y1='" << ly << "' x2='1030' y2='" << ly << "' stroke='" << colour(s.config.settings)
          << "' stroke-width='2'" << (sobol ? "" : " stroke-dasharray='6,4'") << "/>\n<text x='1036' y='" << ly + 4
          << "' font-size='11'>" << s.config.name << "</text>\n";
        ly += 18;
    }
    o << "<text x='1000' y='" << ly + 10 << "' font-size='10' fill='#555'>bars: min..max</text>\n<text x='1000' y='"
      << ly + 24 << "' font-size='10' fill='#555'>over seeds</text>\n";
    o << "</svg>\n";
    write_file(path, o.str());
}

void print_summary(const std::vector<BenchSeries>& all, const Reference& ref) {
    // Equal time: the longest time every configuration reached, relMSE interpolated log-log between its points.
    double t_common = 1e300;
    for (const BenchSeries& s : all) t_common = std::min(t_common, s.points.back().seconds.mean);
    const BenchSeries* baseline = &all.front();
    for (const BenchSeries& s : all)
        if (s.config.name == "mis/rr/ind") baseline = &s;
    auto at_t = [&](const BenchSeries& s, bool trimmed) {
        std::vector<double> x, y;
        for (const BenchPoint& p : s.points)
            x.push_back(p.seconds.mean), y.push_back(trimmed ? p.rel_mse_trimmed.mean : p.rel_mse.mean);
        return interpolate_loglog(x, y, t_common).value_or(y.back());
    };
    const double base_err = at_t(*baseline, false), base_trim = at_t(*baseline, true);
    std::printf("\n### Equal time: relMSE at %.3f s (interpolated log-log between power-of-two spp points)\n\n",
                t_common);
    std::printf(
        "| config | relMSE at %.3g s | relative to %s | trimmed relMSE (top 0.1%% dropped) | relative | spp "
        "reached in budget | seconds | slope vs spp | slope vs time | Mrays/s | rays/sample | path length |\n",
        t_common, baseline->config.name.c_str());
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const BenchSeries& s : all) {
        const BenchPoint& last = s.points.back();
        const double e = at_t(s, false), et = at_t(s, true);
        std::printf("| %s | %.4g | %.3f | %.4g | %.3f | %u | %.3f | %.2f | %.2f | %.2f | %.2f | %.2f |\n",
                    s.config.name.c_str(), e, e / base_err, et, et / base_trim, last.spp, last.seconds.mean,
                    s.slope_spp.slope, s.slope_time.slope, last.mrays_per_s, last.rays_per_sample,
                    last.mean_path_length);
    }
    // The reference check: its own error must be far below the smallest error measured against it.
    double smallest = 1e300;
    for (const BenchSeries& s : all)
        for (const BenchPoint& p : s.points) smallest = std::min(smallest, p.rel_mse.mean);
    std::printf("\nReference: %s\n", ref.origin.c_str());
    if (ref.expected_rel_mse < 0) {
        std::printf(
            "WARNING: the reference's own error is unknown (no pathview:expected_rel_mse in the EXR); "
            "errors below its noise cannot be trusted.\n");
    } else {
        const double ratio = ref.expected_rel_mse / smallest;
        std::printf("Reference's estimated relMSE %.3g = %.1f%% of the smallest measured relMSE %.3g: %s\n",
                    ref.expected_rel_mse, 100.0 * ratio, smallest,
                    ratio <= 0.1 ? "converged enough (<= 10%)"
                                 : "WARNING: NOT converged enough (> 10%): the smallest errors and the slopes are "
                                   "inflated by the reference's noise; raise --reference-spp");
    }
}

}  // namespace pv::app
