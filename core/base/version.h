// core/base/version.h: the pathview version, shown by --version and recorded in partial renders
// (core/partial/partial.h), which refuse to merge across versions.
#pragma once

namespace pv {

inline constexpr char kVersion[] = "0.1";

}  // namespace pv
