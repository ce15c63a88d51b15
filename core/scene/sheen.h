// core/scene/sheen.h: the Charlie sheen lobe of KHR_materials_sheen (Estevez and Kulla 2017, "Production Friendly
// Microfacet Sheen BRDF"), and its tabulated directional albedo for layering by albedo scaling (issue 37 item 2):
//   f_sheen = sheen_color * D(h) G(wo, wi) / (4 cos_o cos_i),  D(h) = (2 + 1/a) sin(theta_h)^(1/a) / (2 pi),
//   G = 1 / (1 + Lambda(cos_o) + Lambda(cos_i)) with the paper's fitted Lambda (no terminator softening),
//   a = sheenRoughness^2 clamped to >= kSheenMinAlpha.
// To be layered over a base by albedo scaling (f_base weighted by 1 - max(sheen_color) E(mu, a), E from
// sheen_albedo()); this file holds the lobe and its table only, not yet the layering. Local frame, +z the
// shading normal, reflection on the side of wo only (as the other reflection lobes, two-sided).
#pragma once

#include "core/base/math.h"

namespace pv {

constexpr float kSheenMinAlpha = 0.01f;  // below it sin^(1/a) is a spike at grazing h no table grid resolves

float sheen_d(float cos_h, float alpha);
float sheen_lambda(float cos_t, float alpha);
// The lobe with sheen colour 1, without the cosine (0 unless wo and wi are strictly on the same side).
float sheen_eval(vec3 wo, vec3 wi, float alpha);
// Directional albedo of sheen_eval (sheen colour 1) at |cos_o| = mu: bilinear in the table written by
// scripts/make_sheen_table.py (core/scene/sheen_table.h).
float sheen_albedo(float mu, float alpha);

}  // namespace pv
