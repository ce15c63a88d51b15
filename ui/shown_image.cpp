// ui/shown_image.cpp: the accumulation on screen (see shown_image.h).
#include "shown_image.h"

#include <utility>

namespace pv::ui {

bool ShownImage::update(const std::function<bool(Snapshot&)>& latest) {
    if (!latest(m_incoming) || m_incoming.generation < m_shown.generation) return false;
    std::swap(m_shown, m_incoming);
    m_incoming.serial = m_shown.serial;  // latest() copies only what is newer than this
    // m_incoming now holds the snapshot shown before: the backdrop when this one is the first with a region.
    auto whole = [](const Snapshot& s) { return s.region == PixelRect{0, 0, s.width, s.height}; };
    if (!whole(m_shown) && m_incoming.width > 0 && whole(m_incoming)) {
        m_backdrop = m_incoming.denoised.empty() ? m_incoming.rgb : m_incoming.denoised;
        m_backdrop_w = m_incoming.width;
        m_backdrop_h = m_incoming.height;
    }
    m_region_active = !whole(m_shown);
    if (m_region_active) composite();
    if (m_shown.generation != m_history_generation) {
        m_history.clear();
        m_history_generation = m_shown.generation;
    }
    // Samples taken per pixel on average: the passes without adaptive sampling.
    const double pixels = double(m_shown.width) * double(m_shown.height);
    const double spp = pixels > 0.0 && m_shown.paths > 0 ? double(m_shown.paths) / pixels : double(m_shown.spp);
    m_history.add(spp, m_shown.seconds, m_shown.rel_mse);
    return true;
}

void ShownImage::composite() {
    m_displayed = m_shown;
    const PixelRect& r = m_shown.region;
    const int w = m_shown.width, h = m_shown.height;
    const bool backdrop = m_backdrop_w > 0 && m_backdrop.size() == size_t(m_backdrop_w) * size_t(m_backdrop_h) * 3;
    for (std::vector<float>* img : {&m_displayed.rgb, &m_displayed.denoised}) {
        if (img->size() != size_t(w) * size_t(h) * 3) continue;  // e.g. no denoised image
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (r.contains(x, y)) continue;
                float* px = img->data() + (size_t(y) * size_t(w) + size_t(x)) * 3;
                if (!backdrop) {
                    px[0] = px[1] = px[2] = 0.f;
                    continue;
                }
                const size_t bx = size_t(x) * size_t(m_backdrop_w) / size_t(w);
                const size_t by = size_t(y) * size_t(m_backdrop_h) / size_t(h);
                const float* b = m_backdrop.data() + (by * size_t(m_backdrop_w) + bx) * 3;
                for (int c = 0; c < 3; ++c) px[c] = b[c] * kDimming;
            }
    }
}

void ShownImage::reset() {
    m_region_active = false;
    m_backdrop.clear();
    m_backdrop_w = m_backdrop_h = 0;
    m_shown = Snapshot{};
    m_incoming = Snapshot{};
    m_history.clear();
    m_history_generation = 0;
}

}  // namespace pv::ui
