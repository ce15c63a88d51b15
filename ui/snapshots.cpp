// ui/snapshots.cpp: snapshot requests and their status (see snapshots.h).
#include "snapshots.h"

namespace pv::ui {

void Snapshots::save(const Snapshot& shown, ViewState& state) {
    if (shown.spp == 0) {
        state.snapshot_status = "nothing rendered yet";
        state.snapshot_ok = false;
        return;
    }
    const std::string path = m_saver.save(shown);
    state.snapshot_status = "saving " + path;
    state.snapshot_ok = true;
    m_log.line("snapshot-start path=%s spp=%u", path.c_str(), shown.spp);
}

void Snapshots::save_png(const Snapshot& shown, bool denoised, const DisplayParams& display,
                         std::vector<uint8_t> screen, ViewState& state) {
    if (shown.spp == 0) {
        state.snapshot_status = "nothing rendered yet";
        state.snapshot_ok = false;
        return;
    }
    Image image(shown.width, shown.height);
    image.rgb = denoised && shown.denoised.size() == shown.rgb.size() ? shown.denoised : shown.rgb;
    const DisplayTransform t = display_transform(display);
    const std::string path = m_saver.save_png(std::move(image), shown.spp, t, std::move(screen));
    state.snapshot_status = "saving " + path + " (" + t.describe() + ")";
    state.snapshot_ok = true;
    m_log.line("snapshot-start path=%s spp=%u", path.c_str(), shown.spp);
}

void Snapshots::resumable_requested(ViewState& state) {
    state.snapshot_status = "preparing a resumable snapshot";
    state.snapshot_ok = true;
}

bool Snapshots::save_partial(std::optional<PartialRender> part, ViewState& state) {
    if (!part) return false;
    const uint32_t spp = uint32_t(part->sample_count());
    const std::string path = m_saver.save_partial(std::move(*part));
    state.snapshot_status = "saving " + path + " (resumable)";
    m_log.line("snapshot-start path=%s spp=%u resumable=1", path.c_str(), spp);
    return true;
}

bool Snapshots::poll(ViewState& state) {
    if (!in_flight()) return false;
    for (const SaveResult& r : m_saver.finished()) {
        state.snapshot_ok = r.ok;
        if (r.ok) {
            state.snapshot_status = "saved " + r.path + " (" + std::to_string(r.spp) + " spp)";
            m_log.line("snapshot path=%s spp=%u%s%s", r.path.c_str(), r.spp, r.note.empty() ? "" : " ", r.note.c_str());
        } else {
            state.snapshot_status = r.error;
            m_log.line("snapshot-error path=%s error=%s", r.path.c_str(), r.error.c_str());
        }
    }
    return !in_flight();
}

bool Snapshots::collect(ProgressiveRenderer& renderer, ViewState& state) {
    bool work = save_partial(renderer.take_partial(), state);
    if (std::string refusal = renderer.take_partial_refusal(); !refusal.empty()) {
        state.snapshot_status = std::move(refusal);
        state.snapshot_ok = false;
        work = true;
    }
    return poll(state) || work;
}

void Snapshots::handle(const PanelActions& act, const Snapshot& shown, bool denoised, ProgressiveRenderer& renderer,
                       const std::function<std::vector<uint8_t>()>& screen, ViewState& state) {
    if (act.save) save(shown, state);
    if (act.save_png) {
        // The screen holds exactly the shown image in the colour view without a comparison or a region's backdrop.
        const DisplayParams& d = state.display;
        const bool comparable = d.view == View::Colour && d.compare == CompareView::Off && !state.region;
        save_png(shown, denoised, d, comparable ? screen() : std::vector<uint8_t>{}, state);
    }
    if (act.save_resumable) {
        renderer.request_partial();
        resumable_requested(state);
    }
}

}  // namespace pv::ui
