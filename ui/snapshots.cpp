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
            m_log.line("snapshot path=%s spp=%u", r.path.c_str(), r.spp);
        } else {
            state.snapshot_status = r.error;
            m_log.line("snapshot-error path=%s error=%s", r.path.c_str(), r.error.c_str());
        }
    }
    return !in_flight();
}

}  // namespace pv::ui
