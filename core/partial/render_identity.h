// core/partial/render_identity.h: what must agree for partial renders to merge, as text: the version, the settings
// (RenderSettings::describe(), read back through the table of core/render/settings.h) and the camera (exact flags).
#pragma once

#include <cstdint>
#include <string>

#include "core/render/settings.h"
#include "core/scene/scene.h"

namespace pv {

// What must agree for two partial renders to merge.
struct RenderIdentity {
    std::string version;  // partial_version() of the pathview that wrote it
    uint64_t scene_hash = 0;
    std::string settings;  // RenderSettings::describe()
    std::string camera;    // camera_text()
    int width = 0, height = 0;
};

// The partial file format's version (pathview:partial, core/partial/partial.h).
inline constexpr char kPartialFormat[] = "1";
// "pathview 0.1, partial format 1": written to and required of every partial file.
std::string partial_version();

// The camera as exact render flags ("--eye x,y,z ... --focus-distance d", %.9g) and back. parse_camera throws
// pv::Error naming `what` on malformed text.
std::string camera_text(const CameraDesc& camera);
CameraDesc parse_camera(const std::string& text, const std::string& what);
// RenderSettings::describe() back to settings; throws pv::Error naming `what` unless describe() of the result
// gives `text` again.
RenderSettings parse_settings(const std::string& text, const std::string& what);

}  // namespace pv
