// core/scene/ggx_albedo_table.h: the directional albedo E(mu, alpha) of Fresnel-less single-scattering GGX
// reflection and its average E_avg(alpha) = 2 int E(mu) mu dmu, tabulated by scripts/gen_ggx_albedo.cpp (generated:
// do not edit). Nodes: mu = (i + 0.5) / 32, alpha = max((j / 31)^2, 1e-3).
#pragma once

namespace pv {

constexpr int kGgxAlbedoN = 32;
extern const float kGgxAlbedo[kGgxAlbedoN][kGgxAlbedoN];  // [alpha][mu]
extern const float kGgxAlbedoAvg[kGgxAlbedoN];            // [alpha]

}  // namespace pv
