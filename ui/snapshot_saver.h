// ui/snapshot_saver.h: saves accumulations as FLOAT EXR off the UI thread. Files are numbered pathview-0001.exr,
// pathview-0002.exr... in the snapshot folder (the first number not yet taken); write_exr() writes a temporary
// file and renames it, so a crash never leaves half a snapshot. The destructor waits for writes in flight.
#pragma once

#include <functional>
#include <future>
#include <string>
#include <vector>

#include "core/frame/progressive.h"
#include "core/partial/partial.h"

namespace pv::ui {

struct SaveResult {
    bool ok = false;
    std::string path;
    std::string error;  // when !ok
    uint32_t spp = 0;
};

class SnapshotSaver {
public:
    // on_done runs on the writing thread after each write (the viewer wakes its event loop with it).
    SnapshotSaver(std::string folder, std::function<void()> on_done);
    ~SnapshotSaver();

    // Starts writing the snapshot's mean image with its metadata; returns the path it will have.
    std::string save(const Snapshot& snapshot);
    // Starts writing a partial render (core/partial/partial.h): resumable with `pathview render --resume`.
    std::string save_partial(PartialRender part);
    // Results of the writes that finished since the last call, in the order they were started.
    std::vector<SaveResult> finished();
    size_t in_flight() const { return m_jobs.size(); }

private:
    std::string next_path();
    // Writes with write(path) on a new thread; returns the path.
    std::string start(uint32_t spp, std::function<void(const std::string&)> write);
    std::string m_folder;
    std::function<void()> m_on_done;
    unsigned m_next = 1;
    std::vector<std::future<SaveResult>> m_jobs;
};

}  // namespace pv::ui
