// core/frame/renderer_partial.h: the renderer's film as a partial render (core/partial/partial.h), for
// `pathview render --part` and the viewer's resumable snapshots.
#pragma once

#include <vector>

#include "core/frame/renderer.h"
#include "core/partial/partial.h"

namespace pv {

// The renderer's film and identity (version, scene hash, settings as rendered, camera, size) as a partial render of
// `ranges`, with render_metadata() as info.
PartialRender partial_from_renderer(const Renderer& renderer, std::vector<SampleRange> ranges);

}  // namespace pv
