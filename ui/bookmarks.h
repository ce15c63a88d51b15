// ui/bookmarks.h: the Camera section's bookmarks: jump to a saved camera, or save the current one under a name in
// the scene file (core/load/scene_file.h save_bookmark: a JSON scene file is rewritten, an OBJ gets "<obj>.json").
// Window-free.
#pragma once

#include <string>

#include "panel.h"
#include "view_log.h"

namespace pv::ui {

// act.goto_bookmark (an index into state.bookmarks; others are ignored): the camera becomes the bookmark's and
// act.camera_changed is set. act.save_bookmark (a name): `camera` is saved under it in `scene_file` and in
// state.bookmarks (replacing one of that name); state.bookmark_status says where, or the error (bookmark_ok false,
// state.bookmarks unchanged).
void handle_bookmarks(PanelActions& act, ViewState& state, CameraDesc& camera, const std::string& scene_file,
                      ViewLog& log);

}  // namespace pv::ui
