// core/distribution.h: piecewise-constant distributions on [0,1) and [0,1)^2 (pbrt-v4 PiecewiseConstant1D/2D),
// sampled by inverting the CDF. Densities are with respect to the unit interval / square.
#pragma once

#include "core/math.h"

#include <vector>

namespace pv {

class Distribution1D {
public:
    Distribution1D() = default;
    // f: non-negative weights of n equal cells. An all-zero f becomes uniform.
    explicit Distribution1D(std::vector<float> f);

    // Returns x in [0,1) with density pdf(x); *cell receives the cell index.
    float sample(float u, float* pdf, size_t* cell) const;
    float pdf(float x) const;  // density at x
    float integral() const { return m_integral; }  // mean of f (before the uniform fallback)
    size_t size() const { return m_f.size(); }

private:
    std::vector<float> m_f;
    std::vector<double> m_cdf;  // n + 1 entries, 0 .. 1
    float m_integral = 0.f;
};

class Distribution2D {
public:
    Distribution2D() = default;
    // f: width x height weights, row-major, row 0 first (row = the v / y axis).
    Distribution2D(const std::vector<float>& f, int width, int height);

    // Returns (x, y) in [0,1)^2 with density *pdf.
    vec2 sample(vec2 u, float* pdf) const;
    float pdf(vec2 p) const;
    bool empty() const { return m_rows.empty(); }

private:
    std::vector<Distribution1D> m_rows;  // conditional in x, per row
    Distribution1D m_marginal;           // over rows
};

}  // namespace pv
