// ui/bookmarks.cpp: bookmark jumps and saves (see bookmarks.h).
#include "bookmarks.h"

#include "core/base/error.h"
#include "core/load/scene_file.h"

namespace pv::ui {

void handle_bookmarks(PanelActions& act, ViewState& state, CameraDesc& camera, const std::string& scene_file,
                      ViewLog& log) {
    if (act.goto_bookmark >= 0 && size_t(act.goto_bookmark) < state.bookmarks.size()) {
        camera = state.bookmarks[size_t(act.goto_bookmark)].camera;
        act.camera_changed = true;
        log.line("bookmark go name=%s", state.bookmarks[size_t(act.goto_bookmark)].name.c_str());
    }
    if (!act.save_bookmark.empty()) {
        try {
            const std::string file = pv::save_bookmark(scene_file, act.save_bookmark, camera);
            bool replaced = false;
            for (Scene::Bookmark& b : state.bookmarks)
                if (b.name == act.save_bookmark) b.camera = camera, replaced = true;
            if (!replaced) state.bookmarks.push_back({act.save_bookmark, camera});
            state.bookmark_status = "saved '" + act.save_bookmark + "' in " + file;
            state.bookmark_ok = true;
            log.line("bookmark saved name=%s file=%s", act.save_bookmark.c_str(), file.c_str());
        } catch (const Error& e) {
            state.bookmark_status = e.what();
            state.bookmark_ok = false;
        }
    }
}

}  // namespace pv::ui
