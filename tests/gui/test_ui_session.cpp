// tests/gui/test_ui_session.cpp: the viewer's remaining window-free rooms: the scene on screen and its warnings
// (active_scene.h), bookmarks (bookmarks.h), snapshot requests (snapshots.h), the accumulation on screen
// (shown_image.h), restart requests (restarts.h) and the latency log lines (frame_stats.h). Needs no display.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "active_scene.h"
#include "bookmarks.h"
#include "core/load/scene_file.h"
#include "frame_stats.h"
#include "restarts.h"
#include "shown_image.h"
#include "snapshots.h"
#include "tests/support/temp_dir.h"

namespace pv::ui {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::shared_ptr<const Scene> cornell() { return std::make_shared<const Scene>(load_scene(builtin_scene_path())); }

CameraDesc test_camera() { return CameraDesc{vec3(1.f, 2.f, 3.f), vec3(0.f), vec3(0.f, 1.f, 0.f), 35.f}; }

}  // namespace

TEST(ViewerActiveScene, AdoptResetsTheEditedStateFromTheScene) {
    ViewLog log("");
    ActiveScene active(log);
    ViewState state;
    state.selected_material = 4;
    state.bookmark_status = "old";
    state.bookmarks.push_back({"stale", test_camera()});
    const auto scene = cornell();
    active.adopt(scene, state);
    EXPECT_EQ(&active.scene(), scene.get());
    ASSERT_EQ(state.materials.size(), scene->materials.size());
    EXPECT_EQ(state.selected_material, -1);
    EXPECT_EQ(state.bookmarks.size(), scene->bookmarks.size());
    EXPECT_TRUE(state.bookmark_status.empty());
    EXPECT_EQ(active.file_name(), fs::path(scene->source).filename().string());
    EXPECT_TRUE(active.warnings().empty()) << active.warnings().front();  // the box has a ceiling light
}

TEST(ViewerActiveScene, WarningsFollowMaterialAndEnvironmentEdits) {
    ViewLog log("");
    ActiveScene active(log);
    ViewState state;
    active.adopt(cornell(), state);
    ASSERT_FALSE(active.environment_lit());
    // Every emitter turned off: the image will be black, and the panel says so.
    for (Material& m : state.materials) m.emission = vec3(0.f);
    PanelActions act;
    act.materials_changed = true;
    active.edited(act, state);
    ASSERT_EQ(active.warnings().size(), 1u);
    EXPECT_NE(active.warnings()[0].find("no emitters"), std::string::npos);
    // A bright sky lights the scene again.
    state.environment.background = vec3(1.f);
    act = PanelActions{};
    act.environment_changed = true;
    active.edited(act, state);
    EXPECT_TRUE(active.environment_lit());
    EXPECT_TRUE(active.warnings().empty());
    // An edit elsewhere leaves the warnings alone.
    state.environment.background = vec3(0.f);
    active.edited(PanelActions{}, state);
    EXPECT_TRUE(active.warnings().empty());
}

TEST(ViewerActiveScene, LoadStatusStartedSucceededFailed) {
    ViewLog log("");
    ActiveScene active(log);
    ViewState state;
    active.adopt(cornell(), state);
    state.scene_path = "next.obj";
    active.load_started(state);
    EXPECT_TRUE(state.scene_loading);
    EXPECT_EQ(state.scene_status, "loading next.obj ...");
    active.load_failed(state, "next.obj: cannot open");
    EXPECT_FALSE(state.scene_loading);
    EXPECT_FALSE(state.scene_ok);
    EXPECT_EQ(state.scene_status, "next.obj: cannot open");
    active.load_started(state);
    EXPECT_TRUE(state.scene_ok);
    active.load_succeeded(state);
    EXPECT_FALSE(state.scene_loading);
    EXPECT_TRUE(state.scene_ok);
    EXPECT_EQ(state.scene_status, "loaded next.obj");
}

TEST(ViewerBookmarks, GotoSetsTheCameraAndOutOfRangeIsIgnored) {
    ViewLog log("");
    ViewState state;
    state.bookmarks.push_back({"a", test_camera()});
    CameraDesc camera{vec3(0.f, 0.f, 9.f), vec3(0.f), vec3(0.f, 1.f, 0.f), 50.f};
    PanelActions act;
    act.goto_bookmark = 1;  // no such bookmark
    handle_bookmarks(act, state, camera, "unused.json", log);
    EXPECT_FALSE(act.camera_changed);
    EXPECT_EQ(camera.vfov_deg, 50.f);
    act.goto_bookmark = 0;
    handle_bookmarks(act, state, camera, "unused.json", log);
    EXPECT_TRUE(act.camera_changed);
    EXPECT_EQ(camera.eye, test_camera().eye);
    EXPECT_EQ(camera.vfov_deg, 35.f);
}

namespace {
// The panel's "save bookmark" with the name "front".
void save_front(ViewState& state, CameraDesc camera, const fs::path& file) {
    ViewLog log("");
    PanelActions act;
    act.save_bookmark = "front";
    handle_bookmarks(act, state, camera, file.string(), log);
}
}  // namespace

TEST(ViewerBookmarks, SaveWritesTheSceneFileAndReplacesByName) {
    const test::TestDir dir("pathview-ui");
    const fs::path file = dir.path / "scene.json";
    fs::copy_file(builtin_scene_path(), file);
    ViewState state;
    CameraDesc camera = test_camera();
    save_front(state, camera, file);
    EXPECT_TRUE(state.bookmark_ok) << state.bookmark_status;
    EXPECT_EQ(state.bookmark_status, "saved 'front' in " + file.string());
    ASSERT_EQ(state.bookmarks.size(), 1u);
    camera.vfov_deg = 20.f;
    save_front(state, camera, file);  // same name: replaced, in the state and the file
    ASSERT_EQ(state.bookmarks.size(), 1u);
    EXPECT_EQ(state.bookmarks[0].camera.vfov_deg, 20.f);
    const std::string text = read_text(file);
    EXPECT_NE(text.find("\"front\""), std::string::npos);
    EXPECT_EQ(text.find("\"front\""), text.rfind("\"front\""));
}

TEST(ViewerBookmarks, SaveErrorIsShownAndTheListKept) {
    const test::TestDir dir("pathview-ui");
    const fs::path file = dir.path / "broken.json";
    std::ofstream(file) << "[1, 2]";
    ViewState state;
    save_front(state, test_camera(), file);
    EXPECT_FALSE(state.bookmark_ok);
    EXPECT_NE(state.bookmark_status.find("broken.json"), std::string::npos) << state.bookmark_status;
    EXPECT_TRUE(state.bookmarks.empty());
}

namespace {
// Polls until no write is in flight; returns what the last poll() returned. The deadline (300 s, for a loaded
// sanitizer build) catches a hang only.
bool poll_until_done(Snapshots& snapshots, ViewState& state) {
    bool done = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
    while (snapshots.in_flight() && std::chrono::steady_clock::now() < deadline) {
        done = snapshots.poll(state);
        if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return done;
}

Snapshot small_snapshot(uint32_t spp) {
    Snapshot s;
    s.generation = 1;
    s.width = 2;
    s.height = 1;
    s.rgb = {0.1f, 0.2f, 0.3f, 1.f, 2.f, 3.f};
    s.spp = spp;
    return s;
}
}  // namespace

TEST(ViewerSnapshots, NothingRenderedYetWritesNothing) {
    const test::TestDir dir("pathview-ui");
    ViewLog log("");
    Snapshots snapshots(dir.path.string(), nullptr, log);
    ViewState state;
    snapshots.save(small_snapshot(0), state);
    EXPECT_FALSE(state.snapshot_ok);
    EXPECT_EQ(state.snapshot_status, "nothing rendered yet");
    EXPECT_FALSE(snapshots.in_flight());
    EXPECT_FALSE(snapshots.save_partial(std::nullopt, state));
    EXPECT_TRUE(fs::is_empty(dir.path));
}

TEST(ViewerSnapshots, SaveReportsTheFileWhenWritten) {
    const test::TestDir dir("pathview-ui");
    std::atomic<int> wakes{0};
    ViewLog log("");
    Snapshots snapshots(
        dir.path.string(), [&] { ++wakes; }, log);
    ViewState state;
    snapshots.save(small_snapshot(8), state);
    const std::string path = (dir.path / "pathview-0001.exr").string();
    EXPECT_EQ(state.snapshot_status, "saving " + path);
    EXPECT_TRUE(poll_until_done(snapshots, state));
    EXPECT_TRUE(state.snapshot_ok);
    EXPECT_EQ(state.snapshot_status, "saved " + path + " (8 spp)");
    EXPECT_TRUE(fs::exists(path));
    EXPECT_EQ(wakes.load(), 1);
    state.snapshot_status.clear();
    EXPECT_FALSE(snapshots.poll(state));  // nothing in flight: nothing to report
    EXPECT_TRUE(state.snapshot_status.empty());
}

TEST(ViewerSnapshots, AWriteErrorIsShown) {
    const test::TestDir dir("pathview-ui");
    ViewLog log("");
    Snapshots snapshots((dir.path / "missing-folder").string(), nullptr, log);
    ViewState state;
    snapshots.save(small_snapshot(8), state);
    EXPECT_TRUE(state.snapshot_ok);  // until the write fails
    EXPECT_TRUE(poll_until_done(snapshots, state));
    EXPECT_FALSE(state.snapshot_ok);
    EXPECT_NE(state.snapshot_status.find("missing-folder"), std::string::npos) << state.snapshot_status;
}

namespace {
// A stand-in for ProgressiveRenderer::latest(): publishes `next` once, with a newer serial.
struct FakeLatest {
    std::optional<Snapshot> next;
    uint64_t serial = 0;
    bool operator()(Snapshot& out) {
        if (!next) return false;
        out = *next;
        out.serial = ++serial;
        next.reset();
        return true;
    }
};
Snapshot pass(uint64_t generation, uint32_t spp) {
    Snapshot s;
    s.generation = generation;
    s.spp = spp;
    s.seconds = 0.01 * spp;
    s.rel_mse = 1.0 / spp;
    return s;
}
}  // namespace

TEST(ViewerShownImage, TakesNewerPassesAndRefusesOlderGenerations) {
    ShownImage image;
    FakeLatest latest;
    auto fn = [&](Snapshot& s) { return latest(s); };
    EXPECT_FALSE(image.update(fn));  // nothing published
    latest.next = pass(2, 2);
    EXPECT_TRUE(image.update(fn));
    EXPECT_EQ(image.shown().generation, 2u);
    EXPECT_EQ(image.history().size(), 1u);
    latest.next = pass(1, 64);  // a pass of the request before the restart lands late
    EXPECT_FALSE(image.update(fn));
    EXPECT_EQ(image.shown().spp, 2u);
    latest.next = pass(2, 4);
    EXPECT_TRUE(image.update(fn));
    EXPECT_EQ(image.history().size(), 2u);
    latest.next = pass(3, 2);  // a new generation: its own history
    EXPECT_TRUE(image.update(fn));
    EXPECT_EQ(image.history().size(), 1u);
    image.reset();  // a new renderer: generation 1 is shown again
    EXPECT_EQ(image.shown().generation, 0u);
    latest.next = pass(1, 2);
    EXPECT_TRUE(image.update(fn));
    EXPECT_EQ(image.history().size(), 1u);
}

// With a render region the display keeps the last whole image outside it, dimmed (scaled to a coarse pass's size);
// shown() (what snapshots save) stays black outside.
TEST(ViewerShownImage, RegionKeepsTheLastImageOutsideDimmed) {
    ShownImage image;
    FakeLatest latest;
    auto fn = [&](Snapshot& s) { return latest(s); };
    Snapshot whole = pass(1, 4);
    whole.width = 4;
    whole.height = 2;
    whole.region = PixelRect{0, 0, 4, 2};
    whole.rgb.assign(4 * 2 * 3, 0.f);
    for (int i = 0; i < 8; ++i) whole.rgb[size_t(i) * 3] = float(i + 1);  // red = pixel number + 1
    latest.next = whole;
    ASSERT_TRUE(image.update(fn));
    EXPECT_EQ(&image.displayed(), &image.shown());
    Snapshot region = pass(2, 1);  // at half resolution: 2x1, the region its right pixel
    region.width = 2;
    region.height = 1;
    region.region = PixelRect{1, 0, 2, 1};
    region.rgb = {0.f, 0.f, 0.f, 9.f, 9.f, 9.f};
    latest.next = region;
    ASSERT_TRUE(image.update(fn));
    const Snapshot& d = image.displayed();
    ASSERT_EQ(d.rgb.size(), 6u);
    EXPECT_FLOAT_EQ(d.rgb[0], 1.f * ShownImage::kDimming);  // the backdrop's pixel (0, 0), dimmed
    EXPECT_EQ(d.rgb[3], 9.f);                               // inside: the region's accumulation
    EXPECT_EQ(image.shown().rgb[0], 0.f);                   // saved snapshots: black outside
    // Cleared: the whole image again.
    latest.next = whole;
    latest.next->generation = 3;
    ASSERT_TRUE(image.update(fn));
    EXPECT_EQ(&image.displayed(), &image.shown());
}

TEST(ViewerRestarts, ReasonListsTheChangesInOrder) {
    PanelActions act;
    EXPECT_EQ(restart_reason(act, false, false), "");
    EXPECT_EQ(restart_reason(act, true, false), "camera");
    act.frame_all = true;
    act.materials_changed = true;
    act.restart = true;
    EXPECT_EQ(restart_reason(act, false, true), "camera,material,resize,restart");
    PanelActions act2;
    act2.settings_changed = act2.environment_changed = true;
    EXPECT_EQ(restart_reason(act2, false, false), "settings,environment");
    PanelActions act3;
    act3.control_changed = true;  // pause and targets never restart
    EXPECT_EQ(restart_reason(act3, false, false), "");
}

TEST(ViewerRestarts, RequestAtTheLevelWithEditsOnlyWhenChanged) {
    ViewState state;
    state.settings.max_depth = 7;
    state.materials.resize(3);
    state.environment.background = vec3(0.5f);
    const RenderRequest coarse = make_request(state, test_camera(), 402, 301, 4, false, false);
    EXPECT_EQ(coarse.width, 100);
    EXPECT_EQ(coarse.height, 75);
    EXPECT_EQ(coarse.settings.max_depth, 7);
    EXPECT_EQ(coarse.camera.eye, test_camera().eye);
    EXPECT_TRUE(coarse.materials.empty());  // empty: keep the renderer's
    EXPECT_FALSE(coarse.environment);
    const RenderRequest full = make_request(state, test_camera(), 3, 2, 4, true, true);
    EXPECT_EQ(full.width, 1);  // never empty
    EXPECT_EQ(full.height, 1);
    EXPECT_EQ(full.materials.size(), 3u);
    ASSERT_TRUE(full.environment);
    EXPECT_EQ(full.environment->background, vec3(0.5f));
}

TEST(ViewerRestarts, PostedRequestReachesTheScheduleAndTheLog) {
    const test::TestDir dir("pathview-ui");
    const fs::path log_path = dir.path / "view.log";
    {
        ViewLog log(log_path.string());
        ProgressiveRenderer renderer(cornell(), 1);
        RefinementSchedule schedule;
        ViewState state;
        const RefinementSchedule::Restart restart = schedule.coarse("initial", 0.0);
        post_restart(renderer, schedule, restart,
                     make_request(state, renderer.scene().camera, 16, 16, schedule.level(), false, false), log, 0.0);
        EXPECT_EQ(schedule.posted_generation(), 1u);
        // The first pass of generation 1 on screen completes the request: one "frame" line.
        Snapshot shown = pass(1, 1);
        shown.width = shown.height = 4;
        log_frames_shown(log, schedule, shown, 0.25);
        log_frames_shown(log, schedule, shown, 0.5);  // already counted
    }
    const std::string text = read_text(log_path);
    EXPECT_NE(text.find("restart gen=1 reason=initial size=4x4 level=4"), std::string::npos) << text;
    EXPECT_NE(text.find("frame gen=1 shown_gen=1 latency_ms=250.0 reason=initial size=4x4 spp=1"), std::string::npos)
        << text;
    EXPECT_EQ(text.find("frame gen="), text.rfind("frame gen="));
}

}  // namespace pv::ui
