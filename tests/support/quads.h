// tests/support/quads.h: small helpers of the ray-robustness tests, whose scenes are quads added with add_quad (two
// triangles each, in order): pi in double, and which quad a hit's primitive belongs to.
#pragma once

#include <cstdint>

namespace pv::test {

inline constexpr double kPiD = 3.14159265358979323846;

// The quad (the add_quad call, counted from 0) that triangle `prim` belongs to; -1 for no hit (kNoIndex).
int face_of(uint32_t prim);

}  // namespace pv::test
