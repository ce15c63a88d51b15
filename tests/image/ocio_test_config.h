// tests/image/ocio_test_config.h: a tiny OpenColorIO 2 config for the tests, written by the test itself (no
// network, no Blender config): linear as scene_linear, display sRGB with the sRGB curve (view Standard) and a pure
// 2.2 gamma (view Gamma 2.2), display Raw with the identity.
#pragma once

#include <string>

namespace pv::test {

inline const char* const kOcioTestConfig = R"(ocio_profile_version: 2

roles:
  scene_linear: linear
  default: linear

file_rules:
  - !<Rule> {name: Default, colorspace: default}

displays:
  sRGB:
    - !<View> {name: Standard, colorspace: srgb}
    - !<View> {name: Gamma 2.2, colorspace: gamma22}
  Raw:
    - !<View> {name: Linear, colorspace: linear}

colorspaces:
  - !<ColorSpace>
    name: linear
    isdata: false
  - !<ColorSpace>
    name: srgb
    from_scene_reference: !<ExponentWithLinearTransform> {gamma: 2.4, offset: 0.055, direction: inverse}
  - !<ColorSpace>
    name: gamma22
    from_scene_reference: !<ExponentTransform> {value: 2.2, direction: inverse}
)";

}  // namespace pv::test
