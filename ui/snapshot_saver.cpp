// ui/snapshot_saver.cpp: one std::async task per snapshot; the image is copied so rendering goes on.
#include "snapshot_saver.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "core/image/image_io.h"

namespace pv::ui {

SnapshotSaver::SnapshotSaver(std::string folder, std::function<void()> on_done)
    : m_folder(folder.empty() ? "." : std::move(folder)), m_on_done(std::move(on_done)) {}

SnapshotSaver::~SnapshotSaver() {
    for (auto& job : m_jobs) job.wait();
}

std::string SnapshotSaver::next_path(const char* ext) {
    namespace fs = std::filesystem;
    for (;; ++m_next) {
        char exr[32], png[32];
        std::snprintf(exr, sizeof exr, "pathview-%04u.exr", m_next);
        std::snprintf(png, sizeof png, "pathview-%04u.png", m_next);
        std::error_code ec;
        if (!fs::exists(fs::path(m_folder) / exr, ec) && !fs::exists(fs::path(m_folder) / png, ec)) {
            ++m_next;
            return (fs::path(m_folder) / (std::string(exr, 13) + ext)).string();
        }
    }
}

std::string SnapshotSaver::start(uint32_t spp, const char* ext, std::function<std::string(const std::string&)> write) {
    const std::string path = next_path(ext);
    m_jobs.push_back(std::async(std::launch::async, [path, spp, write = std::move(write), done = m_on_done] {
        SaveResult r;
        r.path = path;
        r.spp = spp;
        try {
            r.note = write(path);
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
    return start(s.spp, ".exr", [image = std::move(image), metadata = s.metadata](const std::string& path) {
        write_exr(path, image, metadata);
        return std::string();
    });
}

std::string SnapshotSaver::save_png(Image image, uint32_t spp, DisplayTransform transform,
                                    std::vector<uint8_t> screen) {
    return start(
        spp, ".png",
        [image = std::move(image), t = std::move(transform), screen = std::move(screen)](const std::string& path) {
            const std::vector<uint8_t> bytes = display_bytes(image, t);
            write_png_bytes(path, image.width, image.height, bytes);
            std::string note = "transform=" + std::string(name_of(kViewTransformNames, t.transform));
            if (screen.size() == bytes.size()) {
                size_t differ = 0;
                int largest = 0;
                for (size_t i = 0; i < bytes.size(); ++i) {
                    const int d = std::abs(int(bytes[i]) - int(screen[i]));
                    differ += d != 0;
                    largest = std::max(largest, d);
                }
                note += " screen_diff_bytes=" + std::to_string(differ) + "/" + std::to_string(bytes.size()) +
                        " screen_max_diff=" + std::to_string(largest);
            }
            return note;
        });
}

std::string SnapshotSaver::save_partial(PartialRender part) {
    const uint32_t spp = uint32_t(part.sample_count());
    return start(spp, ".exr", [part = std::move(part)](const std::string& path) {
        write_partial(path, part);
        return std::string();
    });
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
