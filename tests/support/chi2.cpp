// tests/support/chi2.cpp: see chi2.h.
#include "tests/support/chi2.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "tests/support/stats.h"

namespace pv::test {

Chi2Result chi2_test(const DirectionSampler& sample, const DirectionPdf& pdf, const Chi2Options& o) {
    Chi2Result r;
    const int nphi = o.res_phi, ncos = o.res_cos;
    const size_t cells = size_t(nphi) * size_t(ncos);
    std::vector<double> observed(cells, 0.0), expected(cells, 0.0);
    const double dphi = 2.0 * M_PI / nphi, dcos = 2.0 / ncos;

    // 1. Histogram.
    Pcg32 rng(o.seed, o.seed * 0x9e3779b97f4a7c15ull + 1);
    size_t produced = 0;
    for (size_t i = 0; i < o.sample_count; ++i) {
        const std::optional<vec3> w = sample(rng);
        if (!w) continue;
        const vec3 d = *w;
        const float len = glm::length(d);
        if (!is_finite(d) || std::fabs(len - 1.f) > 1e-4f) {
            std::ostringstream s;
            s << "sample " << i << " is not a unit vector: (" << d.x << ", " << d.y << ", " << d.z << ")";
            r.message = s.str();
            return r;
        }
        const double phi = std::atan2(double(d.y), double(d.x));
        const int ip = std::clamp(int((phi + M_PI) / dphi), 0, nphi - 1);
        const int ic = std::clamp(int((double(d.z) + 1.0) / dcos), 0, ncos - 1);
        observed[size_t(ic) * size_t(nphi) + size_t(ip)] += 1.0;
        ++produced;
    }
    r.sampled_fraction = double(produced) / double(o.sample_count);

    // 2. Expected counts: adaptive Simpson over each cell (a cell is split in four until the quarters agree
    //    with the whole to a tolerance well below the cell's Poisson noise), so discontinuous pdfs (light edges)
    //    and sharp lobes are integrated accurately.
    const double n_samples = double(o.sample_count);
    bool pdf_ok = true;
    vec3 bad_w(0.f);
    double bad_p = 0.0;
    auto eval_pdf = [&](double phi, double z) {
        z = std::clamp(z, -1.0, 1.0);
        const double sr = std::sqrt(std::max(0.0, 1.0 - z * z));
        const vec3 w(float(sr * std::cos(phi)), float(sr * std::sin(phi)), float(z));
        const double p = pdf(w);
        if (!(p >= 0.0) || !std::isfinite(p)) {
            if (pdf_ok) bad_w = w, bad_p = p;
            pdf_ok = false;
            return 0.0;
        }
        return p;
    };
    const int m = std::max(2, o.ires + (o.ires & 1));
    std::vector<double> wts(size_t(m) + 1);
    for (int k = 0; k <= m; ++k) wts[size_t(k)] = (k == 0 || k == m) ? 1.0 : (k & 1 ? 4.0 : 2.0);
    auto simpson = [&](double p0, double p1, double z0, double z1) {
        double acc = 0.0;
        for (int a = 0; a <= m; ++a)
            for (int b = 0; b <= m; ++b)
                acc += wts[size_t(a)] * wts[size_t(b)] * eval_pdf(p0 + (p1 - p0) * b / m, z0 + (z1 - z0) * a / m);
        return acc * ((p1 - p0) / m / 3.0) * ((z1 - z0) / m / 3.0);
    };
    std::function<double(double, double, double, double, double, double, int)> adapt =
        [&](double p0, double p1, double z0, double z1, double whole, double tol, int depth) -> double {
        const double pm = 0.5 * (p0 + p1), zm = 0.5 * (z0 + z1);
        const double q[4] = {simpson(p0, pm, z0, zm), simpson(pm, p1, z0, zm), simpson(p0, pm, zm, z1),
                             simpson(pm, p1, zm, z1)};
        const double sum = q[0] + q[1] + q[2] + q[3];
        if (depth >= 8 || std::fabs(sum - whole) <= tol) return sum;
        return adapt(p0, pm, z0, zm, q[0], 0.5 * tol, depth + 1) + adapt(pm, p1, z0, zm, q[1], 0.5 * tol, depth + 1) +
               adapt(p0, pm, zm, z1, q[2], 0.5 * tol, depth + 1) + adapt(pm, p1, zm, z1, q[3], 0.5 * tol, depth + 1);
    };
    double integral = 0.0;
    for (int ic = 0; ic < ncos; ++ic)
        for (int ip = 0; ip < nphi; ++ip) {
            const double p0 = -M_PI + ip * dphi, p1 = p0 + dphi, z0 = -1.0 + ic * dcos, z1 = z0 + dcos;
            const double whole = simpson(p0, p1, z0, z1);
            // Tolerance: 10% of the cell's Poisson standard deviation (adds ~0.01 per cell to chi2), in probability
            // units.
            const double tol = 0.1 * std::sqrt(std::max(whole * n_samples, 1.0)) / n_samples;
            const double cell_integral = adapt(p0, p1, z0, z1, whole, tol, 0);
            integral += cell_integral;
            expected[size_t(ic) * size_t(nphi) + size_t(ip)] = cell_integral * n_samples;
        }
    if (!pdf_ok) {
        std::ostringstream s;
        s << "pdf is " << bad_p << " at (" << bad_w.x << ", " << bad_w.y << ", " << bad_w.z << ")";
        r.message = s.str();
        return r;
    }
    r.pdf_integral = integral;
    if (integral > 1.0 + 1e-3 || r.sampled_fraction > 1.0) {
        std::ostringstream s;
        s << "pdf integrates to " << integral << " (sampled fraction " << r.sampled_fraction << ")";
        r.message = s.str();
        return r;
    }

    // 3. Pearson statistic with pooling of low expected counts.
    std::vector<size_t> order(cells);
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    const double min_exp = 5.0;
    double chi2 = 0.0, pool_obs = 0.0, pool_exp = 0.0;
    int terms = 0;
    for (size_t idx : order) {
        const double e = expected[idx], ob = observed[idx];
        if (e == 0.0) {
            if (ob > 0.0) {
                std::ostringstream s;
                s << ob << " samples in a cell with expected count 0 (cos " << (-1.0 + (idx / nphi + 0.5) * dcos)
                  << ", phi " << (-M_PI + (idx % nphi + 0.5) * dphi) << ")";
                r.message = s.str();
                return r;
            }
            continue;
        }
        if (e < min_exp || (pool_exp > 0.0 && pool_exp < min_exp)) {
            pool_obs += ob;
            pool_exp += e;
            if (pool_exp >= min_exp) {
                chi2 += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
                ++terms;
                pool_obs = pool_exp = 0.0;
            }
            continue;
        }
        chi2 += (ob - e) * (ob - e) / e;
        ++terms;
    }
    if (pool_exp > 0.0) {  // the last partial pool (pbrt adds it too)
        chi2 += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        ++terms;
    }
    r.chi2 = chi2;
    r.dof = terms - 1;
    if (r.dof < 1) {
        r.message = "fewer than 2 cells with enough expected samples";
        return r;
    }
    // 4. p-value against the Sidak level.
    r.p = chi2_p_value(chi2, r.dof);
    r.level = sidak_alpha(o.alpha, o.test_count);
    r.passed = std::isfinite(r.p) && r.p >= r.level;
    std::ostringstream s;
    s << "chi2 = " << chi2 << ", dof = " << r.dof << ", p = " << r.p << " (level " << r.level << "), pdf integral "
      << integral << ", sampled fraction " << r.sampled_fraction;
    r.message = s.str();
    return r;
}

}  // namespace pv::test
