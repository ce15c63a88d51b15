// core/partial/render_identity.cpp: the identity text of partial renders (see render_identity.h).
#include "core/partial/render_identity.h"

#include <cstdio>

#include "core/base/error.h"
#include "core/base/text.h"
#include "core/base/version.h"

namespace pv {

std::string partial_version() { return std::string("pathview ") + kVersion + ", partial format " + kPartialFormat; }

std::string camera_text(const CameraDesc& c) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "--eye %.9g,%.9g,%.9g --target %.9g,%.9g,%.9g --up %.9g,%.9g,%.9g --fov %.9g --aperture %.9g "
                  "--focus-distance %.9g",
                  c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.vfov_deg,
                  c.aperture, c.focus_distance);
    return buf;
}

CameraDesc parse_camera(const std::string& text, const std::string& what) {
    CameraDesc c;
    int used = 0;
    const int got = std::sscanf(text.c_str(),
                                "--eye %f,%f,%f --target %f,%f,%f --up %f,%f,%f --fov %f --aperture %f "
                                "--focus-distance %f%n",
                                &c.eye.x, &c.eye.y, &c.eye.z, &c.target.x, &c.target.y, &c.target.z, &c.up.x, &c.up.y,
                                &c.up.z, &c.vfov_deg, &c.aperture, &c.focus_distance, &used);
    if (got != 12 || size_t(used) != text.size() || camera_text(c) != text)
        throw Error(what + ": camera " + quote_prefix(text) +
                    " is malformed; expected --eye x,y,z --target x,y,z --up x,y,z "
                    "--fov f --aperture a --focus-distance d");
    return c;
}

RenderSettings parse_settings(const std::string& text, const std::string& what) {
    const std::optional<RenderSettings> s = settings_from_text(text);
    if (!s) throw Error(what + ": settings " + quote_prefix(text) + " are not understood by " + partial_version());
    return *s;
}

}  // namespace pv
