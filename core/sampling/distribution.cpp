// core/sampling/distribution.cpp: normalisation in double and Vose's alias-table construction.
#include "core/sampling/distribution.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace pv {

void build_alias_table(const float* w, size_t n, AliasSlot* out) {
    // Scaled probabilities p_i = n w_i / sum; a slot is "small" below 1 (Vose 1991, as in pbrt-v4's AliasTable).
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) sum += double(w[i]);
    std::vector<double> p(n);
    std::vector<uint32_t> small, large;
    small.reserve(n);
    large.reserve(n);
    size_t heaviest = 0;
    for (size_t i = 0; i < n; ++i) {
        p[i] = double(w[i]) / sum * double(n);
        (p[i] < 1.0 ? small : large).push_back(uint32_t(i));
        if (w[i] > w[heaviest]) heaviest = i;
    }
    // Fill each small slot up to 1 with the excess of a large cell.
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back(), l = large.back();
        small.pop_back();
        large.pop_back();
        out[s].q = float(p[s]);
        out[s].alias = l;
        p[l] = (p[l] + p[s]) - 1.0;
        (p[l] < 1.0 ? small : large).push_back(l);
    }
    // What is left is 1 up to rounding: those slots keep their own cell, except a zero-weight cell (left over
    // only through rounding), whose slot goes to the heaviest cell so that it is never chosen.
    for (const uint32_t i : large) out[i] = AliasSlot{1.f, i};
    for (const uint32_t i : small) out[i] = w[i] > 0.f ? AliasSlot{1.f, i} : AliasSlot{0.f, uint32_t(heaviest)};
}

DiscreteDistribution::DiscreteDistribution(const std::vector<double>& weights) {
    const size_t n = weights.size();
    double sum = 0.0;
    for (const double w : weights) sum += w;
    if (n == 0 || !(sum > 0.0) || !std::isfinite(sum)) return;
    // Integer counts summing to 2^kBits: floors of the exact shares, the rest to the largest remainders.
    const uint32_t total = 1u << kBits;
    m_count.resize(n);
    std::vector<double> rest(n);
    uint64_t assigned = 0;
    for (size_t i = 0; i < n; ++i) {
        const double x = weights[i] / sum * double(total);
        m_count[i] = uint32_t(std::floor(x));
        rest[i] = x - std::floor(x);
        assigned += m_count[i];
    }
    while (assigned > total) {  // only if rounding pushed exact-integer shares up: take from the largest
        --*std::max_element(m_count.begin(), m_count.end());
        --assigned;
    }
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = uint32_t(i);
    const size_t missing = size_t(total - assigned);  // < n: each floor lost less than 1
    std::nth_element(order.begin(), order.begin() + std::ptrdiff_t(missing), order.end(),
                     [&](uint32_t a, uint32_t b) { return rest[a] > rest[b] || (rest[a] == rest[b] && a < b); });
    for (size_t j = 0; j < missing; ++j) ++m_count[order[j]];
    m_pmf.resize(n);
    for (size_t i = 0; i < n; ++i) m_pmf[i] = float(double(m_count[i]) / double(total));

    // Slots: the smallest power of two >= the items that can be picked, each of `cap` = 2^kBits / slots values
    // of k. With more than 2^kBits items, at most 2^kBits have a count, one slot (cap 1) each.
    size_t picked = 0;
    for (const uint32_t c : m_count) picked += c > 0;
    uint32_t bits = 0;
    while ((size_t(1) << bits) < std::max<size_t>(n <= total ? n : picked, 1)) ++bits;
    m_shift = uint32_t(kBits) - bits;
    m_mask = (1u << m_shift) - 1u;
    const uint32_t cap = 1u << m_shift;
    const size_t slots = size_t(1) << bits;
    // The items that fill the slots: those with a count first, then count-0 ones (threshold 0) to pad.
    std::vector<uint32_t> cell;
    cell.reserve(slots);
    for (size_t i = 0; i < n; ++i)
        if (m_count[i] > 0) cell.push_back(uint32_t(i));
    for (size_t i = 0; i < n && cell.size() < slots; ++i)
        if (m_count[i] == 0) cell.push_back(uint32_t(i));
    const size_t items = cell.size();
    cell.resize(slots, cell.front());  // padding slots, count 0
    // Vose's method in integers (exact): slot j starts with its item's count; a slot below cap is topped up
    // from one above, which then carries its excess on. The counts sum to slots * cap, so nothing is left over.
    std::vector<uint32_t> left(slots);
    std::vector<uint32_t> small, large;
    for (size_t j = 0; j < slots; ++j) {
        left[j] = j < items ? m_count[cell[j]] : 0u;
        (left[j] < cap ? small : large).push_back(uint32_t(j));
    }
    m_slots.resize(slots);
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back(), l = large.back();
        small.pop_back();
        large.pop_back();
        m_slots[s] = Slot{left[s], cell[s], cell[l]};
        left[l] -= cap - left[s];
        (left[l] < cap ? small : large).push_back(l);
    }
    for (const uint32_t j : large) m_slots[j] = Slot{cap, cell[j], cell[j]};
}

namespace {
// Clamps f[0..n) to finite non-negative values and divides it by its mean, so it becomes a density on [0,1);
// an all-zero f becomes uniform. Returns the mean before normalising (0 for the uniform fallback).
float normalise_density(float* f, size_t n) {
    double total = 0.0;
    for (size_t i = 0; i < n; ++i) {
        f[i] = std::isfinite(f[i]) ? std::max(f[i], 0.f) : 0.f;
        total += double(f[i]) / double(n);
    }
    if (!(total > 0.0)) {
        std::fill(f, f + n, 1.f);
        return 0.f;
    }
    for (size_t i = 0; i < n; ++i) f[i] = static_cast<float>(f[i] / total);
    return static_cast<float>(total);
}
}  // namespace

Distribution1D::Distribution1D(std::vector<float> f) : m_f(std::move(f)) {
    m_integral = normalise_density(m_f.data(), m_f.size());
    m_alias.resize(m_f.size());
    if (!m_f.empty()) build_alias_table(m_f.data(), m_f.size(), m_alias.data());
}

float Distribution1D::pdf(float x) const {
    if (m_f.empty() || !(x >= 0.f) || !(x < 1.f)) return 0.f;
    const size_t i = std::min(static_cast<size_t>(x * float(m_f.size())), m_f.size() - 1);
    return m_f[i];
}

Distribution2D::Distribution2D(const std::vector<float>& f, int width, int height) {
    if (width <= 0 || height <= 0) return;
    m_width = width;
    m_height = height;
    const size_t w = size_t(width), h = size_t(height);
    // Each row becomes its conditional density (in m_pdf for now) and its alias table.
    m_pdf.assign(f.begin(), f.begin() + std::ptrdiff_t(w * h));
    m_conditional.resize(w * h);
    std::vector<float> row_integrals(h);
    for (size_t y = 0; y < h; ++y) {
        row_integrals[y] = normalise_density(m_pdf.data() + y * w, w);
        build_alias_table(m_pdf.data() + y * w, w, m_conditional.data() + y * w);
    }
    m_marginal = Distribution1D(std::move(row_integrals));
    m_one_column = w == 1 && std::all_of(m_conditional.begin(), m_conditional.end(),
                                         [](const AliasSlot& s) { return s.q == 1.f && s.alias == 0; });
    // Joint density = conditional * marginal.
    for (size_t y = 0; y < h; ++y)
        for (size_t x = 0; x < w; ++x) m_pdf[y * w + x] *= m_marginal.pdf_cell(y);
}

float Distribution2D::pdf(vec2 p) const {
    if (m_pdf.empty() || !(p.x >= 0.f) || !(p.x < 1.f) || !(p.y >= 0.f) || !(p.y < 1.f)) return 0.f;
    const size_t col = std::min(static_cast<size_t>(p.x * float(m_width)), size_t(m_width) - 1);
    const size_t row = std::min(static_cast<size_t>(p.y * float(m_height)), size_t(m_height) - 1);
    return m_pdf[row * size_t(m_width) + col];
}

}  // namespace pv
