// ui/snapshot_saver.cpp: one std::async task per snapshot; the image is copied so rendering goes on.
#include "snapshot_saver.h"

#include "core/image_io.h"

#include <cstdio>
#include <filesystem>

namespace pv::ui {

SnapshotSaver::SnapshotSaver(std::string folder, std::function<void()> on_done)
    : m_folder(folder.empty() ? "." : std::move(folder)), m_on_done(std::move(on_done)) {}

SnapshotSaver::~SnapshotSaver() {
    for (auto& job : m_jobs) job.wait();
}

std::string SnapshotSaver::next_path() {
    namespace fs = std::filesystem;
    for (;; ++m_next) {
        char name[32];
        std::snprintf(name, sizeof name, "pathview-%04u.exr", m_next);
        const fs::path p = fs::path(m_folder) / name;
        std::error_code ec;
        if (!fs::exists(p, ec)) {
            ++m_next;
            return p.string();
        }
    }
}

std::string SnapshotSaver::save(const Snapshot& s) {
    const std::string path = next_path();
    Image image(s.width, s.height);
    image.rgb = s.rgb;
    Metadata metadata = s.metadata;
    const uint32_t spp = s.spp;
    m_jobs.push_back(std::async(std::launch::async, [path, spp, image = std::move(image),
                                                     metadata = std::move(metadata), done = m_on_done] {
        SaveResult r;
        r.path = path;
        r.spp = spp;
        try {
            write_exr(path, image, metadata);
            r.ok = true;
        } catch (const std::exception& e) {
            r.error = e.what();
        }
        if (done) done();
        return r;
    }));
    return path;
}

std::vector<SaveResult> SnapshotSaver::finished() {
    std::vector<SaveResult> out;
    while (!m_jobs.empty() && m_jobs.front().wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        out.push_back(m_jobs.front().get());
        m_jobs.erase(m_jobs.begin());
    }
    return out;
}

}  // namespace pv::ui
