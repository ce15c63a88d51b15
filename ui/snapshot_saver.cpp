// ui/snapshot_saver.cpp: one std::async task per snapshot; the image is copied so rendering goes on.
#include "snapshot_saver.h"

#include <cstdio>
#include <filesystem>

#include "core/image/image_io.h"

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

std::string SnapshotSaver::start(uint32_t spp, std::function<void(const std::string&)> write) {
    const std::string path = next_path();
    m_jobs.push_back(std::async(std::launch::async, [path, spp, write = std::move(write), done = m_on_done] {
        SaveResult r;
        r.path = path;
        r.spp = spp;
        try {
            write(path);
            r.ok = true;
        } catch (const std::exception& e) {
            r.error = e.what();
        }
        if (done) done();
        return r;
    }));
    return path;
}

std::string SnapshotSaver::save(const Snapshot& s) {
    Image image(s.width, s.height);
    image.rgb = s.rgb;
    return start(s.spp, [image = std::move(image), metadata = s.metadata](const std::string& path) {
        write_exr(path, image, metadata);
    });
}

std::string SnapshotSaver::save_partial(PartialRender part) {
    const uint32_t spp = uint32_t(part.sample_count());
    return start(spp, [part = std::move(part)](const std::string& path) { write_partial(path, part); });
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
