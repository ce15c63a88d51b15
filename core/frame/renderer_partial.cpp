// core/frame/renderer_partial.cpp: the renderer's film as a partial render (see renderer_partial.h).
#include "core/frame/renderer_partial.h"

#include <utility>

namespace pv {

PartialRender partial_from_renderer(const Renderer& r, std::vector<SampleRange> ranges) {
    RenderIdentity id;
    id.version = partial_version();
    id.scene_hash =
        scene_hash(r.scene(), r.traceable().materials(), r.traceable().environment_settings(), r.traceable().fog());
    id.settings = r.settings_as_rendered().describe();
    id.camera = camera_text(r.camera().desc());
    id.width = r.film().width();
    id.height = r.film().height();
    return make_partial(std::move(id), std::move(ranges), r.film(), render_metadata(r));
}

}  // namespace pv
