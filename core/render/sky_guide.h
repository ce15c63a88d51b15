// core/render/sky_guide.h: a learned sky distribution for next-event estimation in interiors lit through openings
// (docs/sky-guide.md): a piecewise-constant density over the sphere of the sky light that reaches the scene, which
// TraceableScene mixes into the sky's share of environment sampling. Trained by core/render/sky_guide_training.h.
#pragma once

#include <algorithm>
#include <memory>
#include <vector>

#include "core/base/math.h"
#include "core/sampling/distribution.h"

// Why: in a room lit through a window, most sky directions that the sky's own sampling
// picks end on a wall; the directions visible through the opening are a small part of the sphere. A short training
// pre-pass (train_sky_guide, core/render/sky_guide_training.h) traces camera paths, sends shadow rays toward sky
// directions drawn from the sky's own distribution at their vertices, and accumulates, per direction bin, the sky light
// that actually arrives (luminance of beta f |cos| Le V / pdf). The normalised histogram is a piecewise-constant
// density over the sphere; TraceableScene mixes it into the sky's share of environment sampling (see
// traceable_scene.h), keeping the sky's own sampling in the mixture so the estimator stays unbiased whatever the guide
// learned.
//
// Bins: kBands bands equal in y = cos(theta) (world +y up) times kColumns columns equal in phi = atan2(-z, x), so
// every bin has the same solid angle 4 pi / kBins and pdf(dir) = P(bin(dir)) kBins / (4 pi). bin() is the one
// direction-to-bin function, used by pdf() and by the training.

namespace pv {

// A grid of res.x x res.y x res.z cells over the box [lo, hi]; points outside belong to the nearest cell.
struct SkyGuideGrid {
    SkyGuideGrid() = default;
    SkyGuideGrid(glm::ivec3 res, vec3 lo, vec3 hi);
    bool valid() const { return res.x >= 1 && res.y >= 1 && res.z >= 1 && is_finite(lo) && is_finite(scale); }
    int cells() const { return res.x * res.y * res.z; }
    // Cell index (z res.y + y) res.x + x of point p.
    int cell(vec3 p) const {
        const vec3 c = (p - lo) * scale;
        auto axis = [&](int a) { return c[a] > 0.f ? int(std::min(c[a], max[a])) : 0; };  // NaN: 0
        return (axis(2) * res.y + axis(1)) * res.x + axis(0);
    }
    glm::ivec3 res{1};
    vec3 lo{0.f}, scale{0.f}, max{0.5f};  // cell coordinates (p - lo) * scale, clamped to [0, max]
};

class SkyGuide {
public:
    static constexpr int kBands = 8;
    static constexpr int kColumns = 16;
    static constexpr int kBins = kBands * kColumns;

    SkyGuide() = default;
    // From non-negative weights, kBins per cell of `grid` (cell by cell); a cell without weight uses the sum over all
    // cells, and every cell mixes in kGlobalShare of that sum (a few noisy training records must not make a cell ignore
    // the rest). Anything inconsistent, or no weight at all, gives an invalid guide. Non-finite or negative weights
    // count as 0.
    SkyGuide(const std::vector<double>& weights, const SkyGuideGrid& grid);
    static constexpr double kGlobalShare = 0.25;

    // False when the guide learned nothing (no weight anywhere): it must not be sampled.
    bool valid() const { return !m_cells.empty(); }
    // The bin of direction dir (unit), and the cell of point p (clamped to the grid).
    static int bin(vec3 dir);
    int cell(vec3 p) const { return m_grid.cell(p); }
    // Solid-angle density toward dir (unit) from p, or from a point of cell `cell`; 0 for an invalid guide.
    float pdf(vec3 p, vec3 dir) const { return m_cells.empty() ? 0.f : pdf_in(cell(p), dir); }
    float pdf_in(int cell, vec3 dir) const { return m_cells[size_t(cell)].pdf[bin(dir)]; }
    // A direction from p (or from a point of cell `cell`): a bin by the cell's distribution (u_bin in [0, 1)), then
    // uniform over the bin's area (u in [0, 1)^2). The bin's probabilities are exact (DiscreteDistribution's
    // table), and pdf() is built from them. Valid guides only.
    vec3 sample(vec3 p, float u_bin, vec2 u) const { return sample_in(cell(p), u_bin, u); }
    vec3 sample_in(int cell, float u_bin, vec2 u) const;
    const SkyGuideGrid& grid() const { return m_grid; }
    // P(bin) in a cell (valid guides only).
    float probability(int cell, int bin) const { return m_pmf[size_t(cell) * size_t(kBins) + size_t(bin)]; }

private:
    // One cell's pdf and alias table side by side (1 KiB, one flat array over the cells: sampling and the pdf of a
    // cell touch one block, no pointer to follow). A slot packs DiscreteDistribution's (threshold, own, alias) for
    // 128 slots of 2^16 values of k each: threshold << 14 | own << 7 | alias.
    struct alignas(64) CellTable {
        float pdf[kBins];  // P(bin) / the bin's solid angle (4 pi / kBins)
        uint32_t slot[kBins];
    };
    static constexpr uint32_t kSlotShift = DiscreteDistribution::kBits - 7;  // 2^7 = kBins slots
    static_assert(kBins == 128, "the packed slots hold 7-bit bin indices");
    SkyGuideGrid m_grid;
    std::vector<CellTable> m_cells;
    std::vector<float> m_pmf;  // P(bin), cell by cell (not used when sampling)
};

// The training pre-pass (train_sky_guide), what it measures for `--sky-guide auto` and the guide's lifecycle in a
// render: core/render/sky_guide_training.h. This file is what the scene reads (TraceableScene mixes the guide in).

}  // namespace pv
