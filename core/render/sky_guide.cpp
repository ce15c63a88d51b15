// core/render/sky_guide.cpp: the learned sky distribution (see sky_guide.h; its training: sky_guide_training.cpp).
#include "core/render/sky_guide.h"

#include <algorithm>
#include <cmath>

#include "core/sampling/warp.h"
#include "core/scene/environment.h"

namespace pv {

SkyGuideGrid::SkyGuideGrid(glm::ivec3 r, vec3 l, vec3 hi) : res(r), lo(l) {
    scale = vec3(res) / glm::max(hi - lo, vec3(1e-30f));
    max = vec3(res) - vec3(0.5f);  // int() of it is res - 1
}

SkyGuide::SkyGuide(const std::vector<double>& weights, const SkyGuideGrid& grid) {
    if (!grid.valid()) return;
    const size_t cells = size_t(grid.cells()), n = size_t(kBins);
    if (weights.size() != cells * n) return;
    auto clean = [](double w) { return std::isfinite(w) && w > 0.0 ? w : 0.0; };
    std::vector<double> global(n, 0.0);
    for (size_t c = 0; c < cells; ++c)
        for (size_t i = 0; i < n; ++i) global[i] += clean(weights[c * n + i]);
    double global_total = 0.0;
    for (double w : global) global_total += w;
    if (!(global_total > 0.0) || !std::isfinite(global_total)) return;
    std::vector<CellTable> tables(cells);
    std::vector<float> pmf(cells * n);
    std::vector<double> w(n);
    for (size_t c = 0; c < cells; ++c) {
        double total = 0.0;
        for (size_t i = 0; i < n; ++i) total += clean(weights[c * n + i]);
        for (size_t i = 0; i < n; ++i)
            w[i] =
                total > 0.0 ? clean(weights[c * n + i]) + kGlobalShare * total * global[i] / global_total : global[i];
        const DiscreteDistribution d(w);
        // Cannot fail with a positive global total (and 128 items always make 128 slots); stay consistent regardless.
        if (d.empty() || d.slot_count() != n || d.slot_shift() != kSlotShift) return;
        for (size_t i = 0; i < n; ++i) {
            uint32_t threshold, own, alias;
            d.slot(i, &threshold, &own, &alias);
            tables[c].slot[i] = threshold << 14 | own << 7 | alias;
            pmf[c * n + i] = d.pmf(i);
            tables[c].pdf[i] = d.pmf(i) * (float(kBins) / (4.f * kPi));
        }
    }
    m_grid = grid;
    m_cells = std::move(tables);
    m_pmf = std::move(pmf);
}

int SkyGuide::bin(vec3 d) {
    // Fractional band and column, clamped inside the grid before the conversion to int (NaN: 0).
    const float b = (1.f - d.y) * (0.5f * float(kBands));
    const int band = b > 0.f ? int(std::min(b, float(kBands) - 0.5f)) : 0;
    float phi = environment_atan2_approx(-d.z, d.x) * kInv2Pi;  // turns, in [-1/2, 1/2]
    if (phi < 0.f) phi += 1.f;
    const float c = phi * float(kColumns);
    const int col = c > 0.f ? int(std::min(c, float(kColumns) - 0.5f)) : 0;
    return band * kColumns + col;
}

vec3 SkyGuide::sample_in(int cell, float u_bin, vec2 u) const {
    // DiscreteDistribution::sample on the packed table.
    const uint32_t k = std::min(uint32_t(u_bin * 0x1p23f), (1u << DiscreteDistribution::kBits) - 1u);
    const uint32_t slot = m_cells[size_t(cell)].slot[k >> kSlotShift];
    const uint32_t i = (k & ((1u << kSlotShift) - 1u)) < (slot >> 14) ? (slot >> 7) & 127u : slot & 127u;
    const uint32_t band = i / kColumns, col = i % kColumns;
    // Uniform by area: y = cos(theta) uniform in the band, phi uniform in the column.
    const float y = 1.f - 2.f * (float(band) + u.x) / float(kBands);
    const float r = std::sqrt(std::max(0.f, 1.f - y * y));
    const vec2 cs = cos_sin_turns((float(col) + u.y) / float(kColumns));
    return vec3(r * cs.x, y, -r * cs.y);
}

}  // namespace pv
