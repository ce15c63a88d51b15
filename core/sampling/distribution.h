// core/sampling/distribution.h: piecewise-constant distributions on [0,1) and [0,1)^2 (pbrt-v4 PiecewiseConstant1D/2D),
// sampled in O(1) with Walker/Vose alias tables (pbrt-v4 AliasTable). Densities are with respect to the unit
// interval / square.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/base/math.h"

namespace pv {

// One slot of an alias table over n cells: slot i yields cell i with probability q, else cell `alias`.
struct AliasSlot {
    float q = 1.f;
    uint32_t alias = 0;
};

// Builds the n slots of an alias table for weights w[0..n) (non-negative, finite, positive sum; Vose 1991, in
// double). Cell i is chosen with probability w[i] / sum(w) up to the float rounding of the thresholds; a cell of
// weight 0 is never chosen.
void build_alias_table(const float* w, size_t n, AliasSlot* out);

// Picks a cell of the alias table slots[0..n) with u in [0,1): u picks a slot and, by comparing its fractional part
// with the slot's threshold, the slot's own cell or its alias. *offset receives the position in [0,1) inside the
// cell, uniform and independent of the cell (the part of u left over by the choice, rescaled), so sampling stays
// continuous.
inline size_t sample_alias_table(const AliasSlot* slots, size_t n, float u, float* offset) {
    const float s = u * float(n);
    const size_t i = std::min(static_cast<size_t>(s), n - 1);
    const float frac = s - float(i);  // in [0, 1]: 1 only when u * n rounds up to n
    const AliasSlot slot = slots[i];
    if (frac < slot.q) {
        *offset = std::min(frac / slot.q, kOneMinusEpsilon);
        return i;
    }
    *offset = std::min((frac - slot.q) / (1.f - slot.q), kOneMinusEpsilon);
    return slot.alias;
}

// (cell + offset) / n in [0,1), rounded once (in double) so the result stays inside its cell except within half
// an ulp of x of the cell's upper edge. For n a power of two up to 2^24 (the default sky's 1 x 512) the same bits
// in float without a division: float(cell) + offset is the sum rounded once to float, which is what the double sum
// rounds to (it is exact unless offset has bits below 2^-53 of it, and those cannot reach a float rounding
// midpoint, where offset's own ulp is at least 2^-47 of the sum), and scaling by 1/n is exact
// (tests/scene/test_environment_sampling.cpp compares the two).
inline float cell_to_unit_reference(size_t cell, float offset, size_t n) {
    return std::min(float((double(cell) + double(offset)) / double(n)), kOneMinusEpsilon);
}
inline float cell_to_unit(size_t cell, float offset, size_t n) {
    if ((n & (n - 1)) == 0 && n <= (size_t(1) << 24))
        return std::min((float(cell) + offset) * (1.f / float(n)), kOneMinusEpsilon);
    return cell_to_unit_reference(cell, offset, n);
}

// A discrete distribution over n items, sampled in O(1) through an alias table whose probabilities are exact:
// item i has probability count_i / 2^23 (counts from the weights by largest remainder), and sample() realises
// exactly those probabilities for any u uniform on [0,1), continuous or on a grid of spacing 2^-23 or finer (both
// samplers draw multiples of 2^-24, and one selection draw split in two halves still leaves multiples of 2^-23):
// k = floor(u 2^23) is then uniform on [0, 2^23), and the table partitions those k. So an estimator dividing by
// pmf() is unbiased for every item it can pick. An item whose share is below about half a count (2^-24) has
// pmf() = 0 and is never picked; a float CDF instead could give an item probability 0 while its pmf was positive.
class DiscreteDistribution {
public:
    static constexpr int kBits = 23;
    DiscreteDistribution() = default;
    // weights: non-negative and finite, with a positive sum (otherwise the distribution is empty).
    explicit DiscreteDistribution(const std::vector<double>& weights);

    bool empty() const { return m_pmf.empty(); }
    size_t size() const { return m_pmf.size(); }
    // An item with probability pmf(); u in [0,1). Requires !empty().
    size_t sample(float u) const {
        const uint32_t k = std::min(uint32_t(u * 0x1p23f), (1u << kBits) - 1u);
        const Slot slot = m_slots[k >> m_shift];
        return (k & m_mask) < slot.threshold ? slot.own : slot.alias;
    }
    float pmf(size_t i) const { return m_pmf[i]; }  // exactly count_i / 2^23
    uint32_t count(size_t i) const { return m_count[i]; }
    // The table, for a caller that packs several into one array (core/render/sky_guide.h): slot_count() slots, each
    // covering 2^slot_shift() consecutive k = floor(u 2^23); slot j picks its own item for the first `threshold`.
    size_t slot_count() const { return m_slots.size(); }
    uint32_t slot_shift() const { return m_shift; }
    void slot(size_t j, uint32_t* threshold, uint32_t* own, uint32_t* alias) const {
        *threshold = m_slots[j].threshold, *own = m_slots[j].own, *alias = m_slots[j].alias;
    }

private:
    // A slot covers 2^m_shift consecutive k; the first `threshold` of them pick `own`, the rest `alias`.
    struct Slot {
        uint32_t threshold = 0, own = 0, alias = 0;
    };
    std::vector<Slot> m_slots;  // a power of two of them
    std::vector<uint32_t> m_count;
    std::vector<float> m_pmf;
    uint32_t m_shift = 0, m_mask = 0;
};

class Distribution1D {
public:
    Distribution1D() = default;
    // f: non-negative weights of n equal cells (NaN, Inf and negatives count as 0). An all-zero f becomes uniform.
    explicit Distribution1D(std::vector<float> f);

    // Returns x in [0,1) with density pdf(x); *cell receives the cell index. Requires size() > 0.
    float sample(float u, float* pdf, size_t* cell) const {
        float offset = 0.f;
        const size_t i = sample_alias_table(m_alias.data(), m_f.size(), u, &offset);
        if (pdf) *pdf = m_f[i];
        if (cell) *cell = i;
        return cell_to_unit(i, offset, m_f.size());
    }
    float pdf(float x) const;                          // density at x; 0 outside [0,1)
    float pdf_cell(size_t i) const { return m_f[i]; }  // density in cell i < size()
    float integral() const { return m_integral; }      // mean of f (before the uniform fallback)
    size_t size() const { return m_f.size(); }

private:
    std::vector<float> m_f;  // normalised density per cell
    std::vector<AliasSlot> m_alias;
    float m_integral = 0.f;
};

class Distribution2D {
public:
    Distribution2D() = default;
    // f: width x height weights, row-major, row 0 first (row = the v / y axis). Each row is a conditional
    // distribution in x (uniform if all zero); the rows are chosen by their integrals (uniform if all are zero).
    Distribution2D(const std::vector<float>& f, int width, int height);

    // Returns (x, y) in [0,1)^2 with density *pdf; *cell (if given) receives the texel index row * width + column.
    vec2 sample(vec2 u, float* pdf, size_t* cell = nullptr) const {
        float pdf_y = 0.f, offset_x = 0.f;
        size_t row = 0;
        const float y = m_marginal.sample(u.y, &pdf_y, &row);
        const size_t w = size_t(m_width);
        if (m_one_column) {
            // One cell a row, threshold 1: the alias table returns cell 0 and offset min(u.x / 1, 1 - eps), and
            // cell_to_unit(0, offset, 1) is the offset: the same bits without the table or the divisions.
            if (pdf) *pdf = m_pdf[row];
            if (cell) *cell = row;
            return vec2(std::min(u.x, kOneMinusEpsilon), y);
        }
        const size_t col = sample_alias_table(m_conditional.data() + row * w, w, u.x, &offset_x);
        const size_t index = row * w + col;
        if (pdf) *pdf = m_pdf[index];
        if (cell) *cell = index;
        return vec2(cell_to_unit(col, offset_x, w), y);
    }
    float pdf(vec2 p) const;
    float pdf_cell(size_t index) const { return m_pdf[index]; }  // density in texel index = row * width + column
    bool empty() const { return m_pdf.empty(); }
    int width() const { return m_width; }
    int height() const { return m_height; }

private:
    int m_width = 0, m_height = 0;
    bool m_one_column = false;  // width 1 and every row's alias slot a threshold of 1 (sample() skips the table)
    Distribution1D m_marginal;  // over rows
    std::vector<AliasSlot> m_conditional;  // one alias table over x per row, width slots each
    std::vector<float> m_pdf;              // joint density per texel: marginal * conditional
};

}  // namespace pv
