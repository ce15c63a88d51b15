// scripts/gen_ggx_dielectric_albedo.cpp: writes core/scene/ggx_dielectric_table.{h,cpp}, the directional albedo of
// single-scattering GGX reflection weighted by the normalised exact dielectric Fresnel
//   x(c) = clamp((F_exact(c, ior) - f0) / (1 - f0), 0, 1),  f0 = ((ior - 1) / (ior + 1))^2,  c = wo.h,
// that is E_x(mu, alpha, ior) = int x(wo.h) D G1(wo) G1(wi) / (4 mu) dwi, stored as the residual E_x - E(mu) x(mu)
// (E Fresnel-less, so that the steep exact x(mu), evaluated at run time, carries the rise toward grazing and the
// smooth limit) on a 16 x 32 x 32 grid (ior, alpha, mu), the hemispherical average E_x,avg(alpha, ior) = 2 int E_x mu
// dmu of what the run time interpolates, and the hemispherical average of x itself,
// x_avg(ior) = 2 int x(mu) mu dmu (the smooth surface). core/scene/bsdf_pbr.cpp writes the dielectric layer's Fresnel
// as s (F0c + (1 - F0c) x), affine in x, so its albedo is s (F0c E + (1 - F0c) E_x) with E the Fresnel-less GGX
// albedo of core/scene/ggx_albedo_table.h, for any KHR_materials_specular factor and colour.
// Self-contained (double precision); build and run from the repository root:
//   g++ -O2 -std=c++17 -o /tmp/gen_ggx_dielectric_albedo scripts/gen_ggx_dielectric_albedo.cpp &&
//   /tmp/gen_ggx_dielectric_albedo core/scene
// Nodes: mu = (i + 0.5) / 32, alpha = max((j / 31)^2, 1e-3) (as ggx_albedo_table), ior = 1 + 2 k / 15 (1 to 3).
// E_x is integrated by sampling the visible normals (Heitz 2018), where the estimator x f cos_i / pdf is x(wo.h)
// G1(wi) for wi above the horizon and 0 below, on a stratified 128 x 128 grid of (u1, u2); x_avg by the midpoint rule
// on 65536 nodes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace {

constexpr int kN = 32;
constexpr int kIorN = 16;
constexpr double kMinAlpha = 1e-3;
constexpr int kStrata = 128;

double ior_node(int k) { return 1.0 + 2.0 * k / (kIorN - 1); }

double fresnel_dielectric(double c, double eta) {
    c = std::fmin(std::fmax(c, 0.0), 1.0);
    const double sin2_t = (1.0 - c * c) / (eta * eta);
    if (sin2_t >= 1.0) return 1.0;
    const double cos_t = std::sqrt(1.0 - sin2_t);
    const double r_parl = (eta * c - cos_t) / (eta * c + cos_t);
    const double r_perp = (c - eta * cos_t) / (c + eta * cos_t);
    return 0.5 * (r_parl * r_parl + r_perp * r_perp);
}

double fresnel_x(double c, double ior) {
    const double r = (ior - 1.0) / (ior + 1.0), f0 = r * r;
    if (!(f0 < 1.0) || f0 <= 0.0) return 0.0;
    return std::fmin(std::fmax((fresnel_dielectric(c, ior) - f0) / (1.0 - f0), 0.0), 1.0);
}

double g1(double cz, double alpha) {
    if (cz <= 0.0) return 0.0;
    const double c2 = cz * cz, s2 = std::fmax(0.0, 1.0 - c2);
    return 2.0 / (1.0 + std::sqrt(1.0 + alpha * alpha * s2 / c2));
}

// E_x(mu) - E(mu) x(mu): the part of E_x that the exact x(mu) times the Fresnel-less E does not give.
// Also returns the Fresnel-less E(mu) in *e (for the average below).
double albedo_x_residual(double mu, double alpha, double ior, double* e) {
    const double x_mu = fresnel_x(mu, ior);
    double sum_e = 0.0;
    const double wo[3] = {std::sqrt(std::fmax(0.0, 1.0 - mu * mu)), 0.0, mu};
    double vh[3] = {alpha * wo[0], 0.0, wo[2]};
    const double vl = std::sqrt(vh[0] * vh[0] + vh[2] * vh[2]);
    for (double& x : vh) x /= vl;
    const double t1[3] = {0.0, 1.0, 0.0};
    const double t2[3] = {-vh[2], 0.0, vh[0]};  // vh x t1
    double sum = 0.0;
    for (int i = 0; i < kStrata; ++i)
        for (int j = 0; j < kStrata; ++j) {
            const double u1 = (i + 0.5) / kStrata, u2 = (j + 0.5) / kStrata;
            const double r = std::sqrt(u1), phi = 2.0 * M_PI * u2;
            const double p1 = r * std::cos(phi);
            double p2 = r * std::sin(phi);
            const double s = 0.5 * (1.0 + vh[2]);
            p2 = (1.0 - s) * std::sqrt(std::fmax(0.0, 1.0 - p1 * p1)) + s * p2;
            const double p3 = std::sqrt(std::fmax(0.0, 1.0 - p1 * p1 - p2 * p2));
            double h[3];
            for (int k = 0; k < 3; ++k) h[k] = p1 * t1[k] + p2 * t2[k] + p3 * vh[k];
            h[0] *= alpha;
            h[1] *= alpha;
            h[2] = std::fmax(1e-9, h[2]);
            const double hl = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
            for (double& x : h) x /= hl;
            const double d = wo[0] * h[0] + wo[2] * h[2];
            const double wiz = 2.0 * d * h[2] - wo[2];
            if (wiz > 0.0) {
                sum += (fresnel_x(d, ior) - x_mu) * g1(wiz, alpha);
                sum_e += g1(wiz, alpha);
            }
        }
    *e = sum_e / (double(kStrata) * kStrata);
    return sum / (double(kStrata) * kStrata);
}

// One row of n values; braced (an inner array) or not (a one-dimensional array's elements).
void print_row(FILE* c, const double* v, int n, const char* indent, bool braced = true) {
    std::fprintf(c, "%s%s", indent, braced ? "{" : "");
    for (int m = 0; m < n; ++m)
        std::fprintf(c, "%.7ff%s%s", v[m], m + 1 < n ? "," : "",
                     m % 8 == 7 && m + 1 < n ? (std::string("\n ") + indent).c_str()
                     : m + 1 < n             ? " "
                                             : "");
    std::fprintf(c, "%s\n", braced ? "}," : ",");
}

// The run-time interpolation of a row of mu nodes (core/scene/bsdf_pbr.cpp): linear between the cell centres,
// extrapolated linearly over the outer half cells.
double lerp_mu(const double* row, double mu) {
    const double x = std::fmin(std::fmax(mu * kN - 0.5, -0.5), kN - 0.5);
    const int x0 = std::min(std::max(int(x), 0), kN - 2);
    const double t = x - x0;
    return row[x0] + (row[x0 + 1] - row[x0]) * t;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string dir = argc > 1 ? argv[1] : "core/scene";
    static double e[kIorN][kN][kN], avg[kIorN][kN], xavg[kIorN];
    constexpr int kQuad = 65536;
    for (int k = 0; k < kIorN; ++k) {
        const double ior = ior_node(k);
        xavg[k] = 0.0;
        for (int q = 0; q < kQuad; ++q) {
            const double mu = (q + 0.5) / kQuad;
            xavg[k] += 2.0 * fresnel_x(mu, ior) * mu / kQuad;
        }
        for (int a = 0; a < kN; ++a) {
            const double r = double(a) / (kN - 1), alpha = std::fmax(r * r, kMinAlpha);  // roughness nodes
            double e_ggx[kN];
            for (int m = 0; m < kN; ++m) e[k][a][m] = albedo_x_residual((m + 0.5) / kN, alpha, ior, &e_ggx[m]);
            // The average of what the run time evaluates, E x + residual with both interpolated (E clamped to
            // [0, 1] as its lookup is), by the midpoint rule on kQuad nodes: x is steep toward grazing.
            avg[k][a] = 0.0;
            for (int q = 0; q < kQuad; ++q) {
                const double mu = (q + 0.5) / kQuad;
                const double eg = std::fmin(std::fmax(lerp_mu(e_ggx, mu), 0.0), 1.0);
                avg[k][a] += 2.0 * (eg * fresnel_x(mu, ior) + lerp_mu(e[k][a], mu)) * mu / kQuad;
            }
        }
    }
    FILE* h = std::fopen((dir + "/ggx_dielectric_table.h").c_str(), "w");
    FILE* c = std::fopen((dir + "/ggx_dielectric_table.cpp").c_str(), "w");
    if (!h || !c) {
        std::fprintf(stderr, "gen_ggx_dielectric_albedo: cannot write %s/ggx_dielectric_table.{h,cpp}\n", dir.c_str());
        return 1;
    }
    std::fprintf(
        h,
        "// core/scene/ggx_dielectric_table.h: the dielectric layer's albedo, tabulated by\n"
        "// scripts/gen_ggx_dielectric_albedo.cpp (generated: do not edit). E_x(mu, alpha, ior), the directional "
        "albedo of\n// single-scattering GGX reflection weighted by the normalised exact Fresnel x = (F(wo.h) - f0) / "
        "(1 - f0), is\n// E(mu) x(mu) + kGgxDielectricAlbedo, E of core/scene/ggx_albedo_table.h; "
        "kGgxDielectricAlbedoAvg is the\n// hemispherical average of that sum as interpolated, kFresnelDielectricAvg "
        "the smooth surface's x_avg(ior).\n// Nodes: mu = (i + 0.5) / %d, alpha = max((j / %d)^2, 1e-3), ior = 1 + 2 "
        "k / %d.\n#pragma once\n\n"
        "namespace pv {\n\nconstexpr int kGgxDielectricN = %d;     // mu and alpha nodes\n"
        "constexpr int kGgxDielectricIorN = %d;  // ior nodes\n"
        "// The residual E_x(mu) - E(mu) x(mu), [ior][alpha][mu].\n"
        "extern const float kGgxDielectricAlbedo[kGgxDielectricIorN][kGgxDielectricN][kGgxDielectricN];\n"
        "extern const float kGgxDielectricAlbedoAvg[kGgxDielectricIorN][kGgxDielectricN];  // [ior][alpha]\n"
        "extern const float kFresnelDielectricAvg[kGgxDielectricIorN];                      // [ior]\n\n"
        "}  // namespace pv\n",
        kN, kN - 1, kIorN - 1, kN, kIorN);
    std::fprintf(c,
                 "// core/scene/ggx_dielectric_table.cpp: generated by scripts/gen_ggx_dielectric_albedo.cpp (see "
                 "core/scene/ggx_dielectric_table.h).\n#include \"core/scene/ggx_dielectric_table.h\"\n\nnamespace "
                 "pv {\n\n// clang-format off\nconst float "
                 "kGgxDielectricAlbedo[kGgxDielectricIorN][kGgxDielectricN][kGgxDielectricN] = {\n");
    for (int k = 0; k < kIorN; ++k) {
        std::fprintf(c, "  {\n");
        for (int a = 0; a < kN; ++a) print_row(c, e[k][a], kN, "    ");
        std::fprintf(c, "  },\n");
    }
    std::fprintf(c, "};\nconst float kGgxDielectricAlbedoAvg[kGgxDielectricIorN][kGgxDielectricN] = {\n");
    for (int k = 0; k < kIorN; ++k) print_row(c, avg[k], kN, "    ");
    std::fprintf(c, "};\nconst float kFresnelDielectricAvg[kGgxDielectricIorN] = {\n");
    print_row(c, xavg, kIorN, "    ", false);
    std::fprintf(c, "};\n// clang-format on\n\n}  // namespace pv\n");
    std::fclose(h);
    std::fclose(c);
    return 0;
}
