#!/usr/bin/env python3
# scripts/make_sheen_table.py: writes core/scene/sheen_table.h, the directional albedo E(mu, alpha) of the Charlie
# sheen lobe (Estevez and Kulla 2017, "Production Friendly Microfacet Sheen BRDF"; core/scene/sheen.h) with sheen
# colour 1: E = integral over the hemisphere of D(h) G(wo, wi) / (4 cos_o cos_i) cos_i dwi, on a 16 x 16 grid of
# nodes mu = cos_o = i/15 (mu 0 stands for 1e-3) and alpha = j/15 (clamped to kSheenMinAlpha), by the midpoint rule in
# (cos_i, phi) with 256 x 128 cells (phi over [0, pi], the lobe being symmetric in phi). Pure Python, a minute.
# tests/scene/test_sheen.cpp checks the table against its own numerical integration. Run from the repository root.
import math

N = 16
MIN_ALPHA = 0.01  # kSheenMinAlpha in core/scene/sheen.h
NU, NPHI = 256, 128


def lam(cos_t, r):
    # Estevez-Kulla's fitted Lambda, the coefficients interpolated by (1 - r)^2 between r = 0 and r = 1
    t = (1.0 - r) ** 2
    a = t * 25.3245 + (1 - t) * 21.5473
    b = t * 3.32435 + (1 - t) * 3.82987
    c = t * 0.16801 + (1 - t) * 0.19823
    d = t * -1.27393 + (1 - t) * -1.97760
    e = t * -4.85967 + (1 - t) * -4.32054

    def L(x):
        return a / (1.0 + b * x ** c) + d * x + e

    if cos_t < 0.5:
        return math.exp(L(cos_t))
    return math.exp(2.0 * L(0.5) - L(1.0 - cos_t))


def albedo(mu, r):
    so = math.sqrt(max(0.0, 1 - mu * mu))
    wo = (so, 0.0, mu)
    lo = lam(mu, r)
    inv = 1.0 / r
    norm = (2.0 + inv) / (2.0 * math.pi)
    total = 0.0
    for i in range(NU):
        ci = (i + 0.5) / NU
        si = math.sqrt(1 - ci * ci)
        li = lam(ci, r)
        g = 1.0 / (1.0 + lo + li)
        for k in range(NPHI):
            phi = (k + 0.5) / NPHI * math.pi
            wi = (si * math.cos(phi), si * math.sin(phi), ci)
            h = (wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2])
            hl = math.sqrt(h[0] ** 2 + h[1] ** 2 + h[2] ** 2)
            cos_h = h[2] / hl
            sin2 = max(0.0, 1 - cos_h * cos_h)
            d = norm * sin2 ** (0.5 * inv)
            total += d * g / (4.0 * mu)  # f cos_i, f = D G / (4 cos_o cos_i)
    # dwi = d(cos_i) dphi; phi over [0, pi] counted twice
    return total * (1.0 / NU) * (math.pi / NPHI) * 2.0


def main():
    rows = []
    for i in range(N):
        mu = max(i / (N - 1), 1e-3)
        vals = [albedo(mu, max(j / (N - 1), MIN_ALPHA)) for j in range(N)]
        rows.append("    {" + ", ".join("%.6ff" % v for v in vals) + "},  // mu = %d/15" % i)
    with open("core/scene/sheen_table.h", "w") as f:
        f.write("// core/scene/sheen_table.h: written by scripts/make_sheen_table.py (do not edit): the Charlie sheen\n")
        f.write("// lobe's directional albedo, kSheenAlbedo[i][j] at mu = i/15 (0: 1e-3), alpha = j/15 (>= kSheenMinAlpha).\n")
        f.write("#pragma once\n\nnamespace pv::sheen_detail {\n\n// clang-format off\n")
        f.write("inline constexpr float kSheenAlbedo[%d][%d] = {\n" % (N, N))
        f.write("\n".join(rows) + "\n};\n// clang-format on\n\n}  // namespace pv::sheen_detail\n")


if __name__ == "__main__":
    main()
