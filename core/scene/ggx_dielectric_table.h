// core/scene/ggx_dielectric_table.h: the dielectric layer's albedo, tabulated by
// scripts/gen_ggx_dielectric_albedo.cpp (generated: do not edit). E_x(mu, alpha, ior), the directional albedo of
// single-scattering GGX reflection weighted by the normalised exact Fresnel x = (F(wo.h) - f0) / (1 - f0), is
// E(mu) x(mu) + kGgxDielectricAlbedo, E of core/scene/ggx_albedo_table.h; kGgxDielectricAlbedoAvg is the
// hemispherical average of that sum as interpolated, kFresnelDielectricAvg the smooth surface's x_avg(ior).
// Nodes: mu = (i + 0.5) / 32, alpha = max((j / 31)^2, 1e-3), ior = 1 + 2 k / 15.
#pragma once

namespace pv {

constexpr int kGgxDielectricN = 32;     // mu and alpha nodes
constexpr int kGgxDielectricIorN = 16;  // ior nodes
// The residual E_x(mu) - E(mu) x(mu), [ior][alpha][mu].
extern const float kGgxDielectricAlbedo[kGgxDielectricIorN][kGgxDielectricN][kGgxDielectricN];
extern const float kGgxDielectricAlbedoAvg[kGgxDielectricIorN][kGgxDielectricN];  // [ior][alpha]
extern const float kFresnelDielectricAvg[kGgxDielectricIorN];                     // [ior]

}  // namespace pv
