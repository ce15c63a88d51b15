// ui/compare_display.cpp: see compare_display.h.
#include "compare_display.h"

#include <cstdio>
#include <string>
#include <utility>

namespace pv::ui {

void CompareDisplay::set_b(Image image, const std::string& source) {
    m_compare.set_b(std::move(image), source);
    m_display.upload_b(m_compare.b());
    m_log.line("compare %s", m_compare.status().c_str());
}

void CompareDisplay::apply(const CompareActions& act, const Snapshot& displayed, const Snapshot& shown, bool denoising,
                           const CameraDesc& camera, int full_w, int full_h) {
    const std::string status = m_compare.status();
    const std::string source = m_compare.source();
    const CompareView view = m_compare.view();
    if (!m_compare.apply(act, displayed, denoising, camera, full_w, full_h)) return;
    if (m_compare.source() != source || act.hold || !act.load.empty()) m_display.upload_b(m_compare.b());
    upload_difference(displayed, denoising);
    if (m_compare.status() != status || act.hold || !act.load.empty()) {
        m_log.line("compare %s", m_compare.status().c_str());
        if (!m_compare.ok()) std::fprintf(stderr, "%s\n", m_compare.status().c_str());
    }
    if (m_compare.view() != view) m_log.line("compare view=%s", compare_view_name(m_compare.view()));
    m_compare.update(shown);
}

void CompareDisplay::new_pass(const Snapshot& shown, const Snapshot& displayed, bool denoising) {
    m_compare.update(shown);
    log_error(shown, denoising);
    upload_difference(displayed, denoising);
}

void CompareDisplay::upload_difference(const Snapshot& displayed, bool denoising) {
    if (m_compare.view() != CompareView::Difference) return;
    const Snapshot& a = displayed;
    const bool denoised = denoising && a.denoised.size() == a.rgb.size();
    m_display.upload_difference(m_compare.difference((denoised ? a.denoised : a.rgb).data(), a.width, a.height),
                                a.width, a.height);
}

void CompareDisplay::log_error(const Snapshot& s, bool denoising) {
    const auto raw = m_compare.rel_mse();
    if (!raw) return;
    const bool denoised = denoising && m_compare.rel_mse_denoised() >= 0.0;
    m_log.line("error gen=%llu spp=%u denoised_spp=%u shown=%s rel_mse_shown=%.4e rel_mse_raw=%.4e",
               (unsigned long long)s.generation, s.spp, s.denoised_spp,
               denoised ? (s.denoised_nfor ? "nfor" : "atrous") : "raw", denoised ? m_compare.rel_mse_denoised() : *raw,
               *raw);
}

}  // namespace pv::ui
