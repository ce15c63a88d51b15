// tests/support/quads.cpp: see quads.h.
#include "tests/support/quads.h"

#include "core/base/math.h"

namespace pv::test {

int face_of(uint32_t prim) { return prim == kNoIndex ? -1 : int(prim / 2); }

}  // namespace pv::test
