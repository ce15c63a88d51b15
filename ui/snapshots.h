// ui/snapshots.h: the Snapshots section's requests: save the accumulation on screen (Ctrl+S, "Save"), or a
// resumable partial render once the renderer has made it; the writes run off the UI thread (snapshot_saver.h) and
// their outcome reaches ViewState::snapshot_status and the log. Window-free.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "panel.h"
#include "snapshot_saver.h"
#include "view_log.h"

namespace pv::ui {

class Snapshots {
public:
    // Files go to `folder`; `wake` runs on the writing thread after each write (the viewer wakes its loop).
    Snapshots(std::string folder, std::function<void()> wake, ViewLog& log)
        : m_saver(std::move(folder), std::move(wake)), m_log(log) {}

    // Starts saving `shown`; "nothing rendered yet" (not ok) before its first sample.
    void save(const Snapshot& shown, ViewState& state);
    // Starts saving `shown` (its denoised image when `denoised` and it has one) through the display's transform as
    // PNG; `screen`: the display pass's bytes of the same image (empty: not compared).
    void save_png(const Snapshot& shown, bool denoised, const DisplayParams& display, std::vector<uint8_t> screen,
                  ViewState& state);
    // The user asked for a resumable snapshot (the viewer calls ProgressiveRenderer::request_partial()).
    void resumable_requested(ViewState& state);
    // Starts saving the partial render the renderer made, if any; true when one was started.
    bool save_partial(std::optional<PartialRender> part, ViewState& state);
    // Reports the writes that finished; true when the last one in flight did (the panel then needs a frame).
    bool poll(ViewState& state);
    // A frame's save actions: the EXR (act.save), the PNG through the view transform (act.save_png; `screen` gives
    // the display pass's bytes of the same image to compare, when it shows exactly that image), a resumable snapshot
    // (act.save_resumable, requested from `renderer`). `shown` is the accumulation on screen, `denoised` whether its
    // denoised image is shown.
    void handle(const PanelActions& act, const Snapshot& shown, bool denoised, ProgressiveRenderer& renderer,
                const std::function<std::vector<uint8_t>()>& screen, ViewState& state);
    // Once a frame: saves the partial render `renderer` made, reports a refused one and the finished writes; true when
    // the panel needs a frame.
    bool collect(ProgressiveRenderer& renderer, ViewState& state);
    bool in_flight() const { return m_saver.in_flight() > 0; }

private:
    SnapshotSaver m_saver;
    ViewLog& m_log;
};

}  // namespace pv::ui
