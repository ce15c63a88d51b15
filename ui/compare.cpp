// ui/compare.cpp: before/after comparison (see compare.h).
#include "compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include "core/image/image_io.h"
#include "core/image/metrics.h"

namespace pv::ui {
namespace {

bool same_camera(const CameraDesc& a, const CameraDesc& b) {
    return a.eye == b.eye && a.target == b.target && a.up == b.up && a.vfov_deg == b.vfov_deg &&
           a.aperture == b.aperture && a.focus_distance == b.focus_distance;
}

}  // namespace

const char* compare_view_name(CompareView v) {
    switch (v) {
        case CompareView::Split:
            return "A | B";
        case CompareView::ShowB:
            return "B";
        case CompareView::Difference:
            return "|A-B|/(B+0.01)";
        default:
            return "A";
    }
}

bool Compare::apply(const CompareActions& a, const Snapshot& displayed, bool denoised, const CameraDesc& camera,
                    int full_w, int full_h) {
    const bool had_b = has_b();
    const size_t before_size = m_b.rgb.size();
    const CompareView view_before = view();
    const float divider_before = m_divider;
    const std::string source_before = m_source;
    if (a.clear) clear();
    if (a.hold) hold(displayed, denoised, camera);
    if (!a.load.empty()) load(a.load, full_w, full_h);
    if (a.view) set_view(*a.view);
    if (a.cycle)
        set_view(m_view == CompareView::Off     ? CompareView::Split
                 : m_view == CompareView::Split ? CompareView::Difference
                                                : CompareView::Off);
    if (a.flip) {
        if (m_view == CompareView::ShowB) {
            m_view = m_before_flip;
        } else {
            m_before_flip = m_view;
            m_view = CompareView::ShowB;
        }
    }
    if (a.divider && has_b()) {
        m_divider = std::clamp(*a.divider, 0.f, 1.f);
        if (m_view != CompareView::Split) set_view(CompareView::Split);
    }
    return a.hold || a.clear || !a.load.empty() || had_b != has_b() || before_size != m_b.rgb.size() ||
           source_before != m_source || view_before != view() || divider_before != m_divider;
}

void Compare::set_view(CompareView v) {
    m_view = v;
    if (v != CompareView::ShowB) m_before_flip = v;
}

void Compare::hold(const Snapshot& s, bool denoised, const CameraDesc& camera) {
    const size_t n = size_t(std::max(s.width, 0)) * size_t(std::max(s.height, 0)) * 3;
    if (n == 0 || s.rgb.size() != n) {
        m_status = "nothing rendered yet to hold as B";
        m_ok = false;
        return;
    }
    const bool use_denoised = denoised && s.denoised.size() == n;
    m_b = Image{};
    m_b.width = s.width;
    m_b.height = s.height;
    m_b.rgb = use_denoised ? s.denoised : s.rgb;
    m_camera = camera;
    m_from_file = false;
    char buf[96];
    std::snprintf(buf, sizeof buf, "held at %u spp%s", use_denoised ? s.denoised_spp : s.spp,
                  use_denoised ? " (denoised)" : "");
    m_source = buf;
    std::snprintf(buf, sizeof buf, ", %dx%d", s.width, s.height);
    m_status = "B " + m_source + buf;
    m_ok = true;
    if (m_view == CompareView::Off) set_view(CompareView::Split);
    m_rel_mse.reset();
    m_history.clear();
    m_history_generation = 0;
}

bool Compare::load(const std::string& path, int full_w, int full_h) {
    Image img;
    try {
        img = read_exr(path);
    } catch (const std::exception& e) {
        m_status = e.what();
        m_ok = false;
        return false;
    }
    if (full_w > 0 && full_h > 0 && (img.width != full_w || img.height != full_h)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, ": %dx%d pixels; expected the image's %dx%d", img.width, img.height, full_w,
                      full_h);
        m_status = path + buf;
        m_ok = false;
        return false;
    }
    set_b(std::move(img), path);
    return true;
}

void Compare::set_b(Image image, const std::string& source) {
    m_b = std::move(image);
    m_source = source;
    m_from_file = true;
    m_camera.reset();
    char buf[64];
    std::snprintf(buf, sizeof buf, " (%dx%d)", m_b.width, m_b.height);
    m_status = "B from " + source + buf;
    m_ok = true;
    if (m_view == CompareView::Off) set_view(CompareView::Split);
    m_rel_mse.reset();
    m_history.clear();
    m_history_generation = 0;
}

void Compare::clear() {
    m_b = Image{};
    m_source.clear();
    m_from_file = false;
    m_camera.reset();
    m_view = m_before_flip = CompareView::Off;
    m_rel_mse.reset();
    m_history.clear();
    m_history_generation = 0;
    m_status.clear();
    m_ok = true;
}

bool Compare::camera_moved(const CameraDesc& now) const { return has_b() && m_camera && !same_camera(*m_camera, now); }

void Compare::update(const Snapshot& s) {
    m_rel_mse.reset();
    m_rel_mse_denoised = -1.0;
    const size_t n = size_t(std::max(s.width, 0)) * size_t(std::max(s.height, 0)) * 3;
    if (!has_b() || s.width != m_b.width || s.height != m_b.height || n == 0 || s.rgb.size() != n) return;
    m_rel_mse = compare_values(s.rgb.data(), m_b.rgb.data(), n).rel_mse;
    if (s.denoised.size() == n) m_rel_mse_denoised = compare_values(s.denoised.data(), m_b.rgb.data(), n).rel_mse;
    if (s.generation != m_history_generation) {
        m_history.clear();
        m_history_generation = s.generation;
    }
    // ConvergenceHistory ignores points <= 0: an A equal to B has nothing to plot.
    const double pixels = double(s.width) * double(s.height);
    const double spp = s.paths > 0 ? double(s.paths) / pixels : double(s.spp);
    m_history.add(spp, s.seconds, *m_rel_mse);
}

std::vector<float> Compare::difference(const float* a, int w, int h) const {
    std::vector<float> out;
    if (!has_b() || w <= 0 || h <= 0 || !a) return out;
    out.resize(size_t(w) * size_t(h));
    for (int y = 0; y < h; ++y) {
        const size_t by = std::min(size_t(y) * size_t(m_b.height) / size_t(h), size_t(m_b.height - 1));
        for (int x = 0; x < w; ++x) {
            const size_t bx = std::min(size_t(x) * size_t(m_b.width) / size_t(w), size_t(m_b.width - 1));
            const float* pa = a + (size_t(y) * size_t(w) + size_t(x)) * 3;
            const float* pb = m_b.rgb.data() + (by * size_t(m_b.width) + bx) * 3;
            float sum = 0.f;
            for (int c = 0; c < 3; ++c) sum += std::fabs(pa[c] - pb[c]) / (std::fabs(pb[c]) + kEps);
            out[size_t(y) * size_t(w) + size_t(x)] = sum / 3.f;
        }
    }
    return out;
}

}  // namespace pv::ui
