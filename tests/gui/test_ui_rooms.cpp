// tests/gui/test_ui_rooms.cpp: the viewer's window-free rooms: gestures -> camera (navigation.h), the refinement
// schedule (refinement.h) and background scene loads (scene_loader.h). Needs no display.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "core/base/error.h"
#include "core/load/scene_file.h"
#include "light_mix.h"
#include "navigation.h"
#include "refinement.h"
#include "restarts.h"
#include "scene_loader.h"

namespace pv::ui {
namespace {

CameraDesc test_camera() { return CameraDesc{vec3(0.f, 0.f, 10.f), vec3(0.f), vec3(0.f, 1.f, 0.f), 40.f}; }

// A 400x300 image region; every pick hits material 3 at (1, 2, 3).
struct NavFixture {
    ViewLog log{""};
    Navigation nav{log};
    CameraController camera{test_camera(), vec3(-1.f), vec3(1.f)};
    ViewState state;
    InputQueue input;
    NavigationFrame frame;
    int picks = 0;
    NavFixture() {
        frame.image_size = vec2(400.f, 300.f);
        frame.window_height = 300;
        frame.pick = [this](vec2) {
            ++picks;
            PickResult r;
            r.triangle = 7;
            r.material = 3;
            r.position = vec3(1.f, 2.f, 3.f);
            return std::optional<PickResult>(r);
        };
    }
    void button(int b, int action, vec2 pos, double time, int mods = 0) {
        input.buttons.push_back({b, action, mods, pos, time});
    }
    NavigationResult frame_once(PanelActions& act) { return nav.handle(input, frame, camera, state, act); }
};

}  // namespace

TEST(ViewerNavigation, LeftDragOrbitsAboutTheTarget) {
    NavFixture f;
    PanelActions act;
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(100.f, 100.f), 0.0);
    f.frame.cursor = vec2(160.f, 100.f);  // held and moved 60 px
    const NavigationResult r = f.frame_once(act);
    EXPECT_TRUE(r.camera_moved);
    EXPECT_TRUE(f.nav.dragging());
    EXPECT_EQ(f.camera.desc().target, vec3(0.f));
    EXPECT_GT(std::fabs(f.camera.desc().eye.x), 1.f);
    EXPECT_EQ(f.picks, 0);  // a drag is no click
    EXPECT_TRUE(f.input.buttons.empty());
}

TEST(ViewerNavigation, ShiftDragPansAndMiddleDragPans) {
    for (const bool shift : {true, false}) {
        NavFixture f;
        PanelActions act;
        f.button(shift ? GLFW_MOUSE_BUTTON_LEFT : GLFW_MOUSE_BUTTON_MIDDLE, GLFW_PRESS, vec2(100.f, 100.f), 0.0,
                 shift ? GLFW_MOD_SHIFT : 0);
        f.frame.cursor = vec2(150.f, 100.f);
        EXPECT_TRUE(f.frame_once(act).camera_moved);
        EXPECT_LT(f.camera.desc().target.x, 0.f);  // the target moved with the eye
        EXPECT_NEAR(f.camera.desc().target.x, f.camera.desc().eye.x, 1e-4f);
    }
}

// Ctrl+left drag sets a render region in render pixels (here 2 per window pixel) and moves no camera; X clears it.
TEST(ViewerNavigation, CtrlDragSetsARegionAndXClearsIt) {
    NavFixture f;
    f.frame.render_size = vec2(800.f, 600.f);
    const CameraDesc before = f.camera.desc();
    PanelActions act;
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(150.5f, 120.f), 0.0, GLFW_MOD_CONTROL);
    f.frame.cursor = vec2(60.f, 40.f);
    EXPECT_FALSE(f.frame_once(act).camera_moved);
    EXPECT_FALSE(act.region_changed);  // taken at the release
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, vec2(50.f, 30.25f), 0.1, GLFW_MOD_CONTROL);
    EXPECT_FALSE(f.frame_once(act).camera_moved);
    EXPECT_EQ(f.camera.desc().eye, before.eye);
    EXPECT_EQ(f.picks, 0);
    ASSERT_TRUE(act.region_changed);
    ASSERT_TRUE(f.state.region);
    EXPECT_EQ(*f.state.region, (PixelRect{100, 60, 301, 240}));
    // A ctrl+click (no drag) sets nothing; X clears the region.
    PanelActions act2;
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(10.f, 10.f), 1.0, GLFW_MOD_CONTROL);
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, vec2(10.f, 10.f), 1.1, GLFW_MOD_CONTROL);
    f.input.keys.emplace_back(GLFW_KEY_X, 0);
    f.frame_once(act2);
    EXPECT_TRUE(act2.region_changed);
    EXPECT_FALSE(f.state.region);
    EXPECT_EQ(restart_reason(act2, false, false), "region");
}

// The request carries the region at the refinement level's resolution, covering every full-resolution pixel of it;
// none while adaptive sampling is on (the renderer refuses the two together).
TEST(ViewerRestarts, RequestCarriesTheRegionScaledToTheLevel) {
    ViewState state;
    state.region = PixelRect{101, 60, 303, 240};
    const CameraDesc cam = test_camera();
    EXPECT_EQ(make_request(state, cam, 800, 600, 1, false, false).region, state.region);
    EXPECT_EQ(make_request(state, cam, 800, 600, 4, false, false).region, (PixelRect{25, 15, 76, 60}));
    state.region = PixelRect{799, 599, 800, 600};
    EXPECT_EQ(make_request(state, cam, 800, 600, 4, false, false).region, (PixelRect{199, 149, 200, 150}));
    EXPECT_FALSE(make_request(ViewState{}, cam, 800, 600, 1, false, false).region);
    state.adaptive.noise_threshold = 0.05f;
    EXPECT_FALSE(make_request(state, cam, 800, 600, 1, false, false).region);
}

TEST(ViewerNavigation, PressesImGuiWantsOrOutsideTheImageStartNoDrag) {
    NavFixture f;
    PanelActions act;
    f.frame.imgui_wants_mouse = true;
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(100.f, 100.f), 0.0);
    f.frame.cursor = vec2(200.f, 100.f);
    EXPECT_FALSE(f.frame_once(act).camera_moved);
    f.frame.imgui_wants_mouse = false;
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(450.f, 100.f), 0.1);  // on the panel, right of the image
    f.frame.cursor = vec2(350.f, 100.f);
    EXPECT_FALSE(f.frame_once(act).camera_moved);
    EXPECT_EQ(f.camera.desc().eye, test_camera().eye);
}

TEST(ViewerNavigation, ClickSelectsDoubleClickRetargets) {
    NavFixture f;
    PanelActions act;
    // A press and release 2 px apart (under the slop) is a click: select the material under it.
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(100.f, 100.f), 1.0);
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, vec2(102.f, 100.f), 1.05);
    f.frame.cursor = vec2(102.f, 100.f);
    EXPECT_FALSE(f.frame_once(act).camera_moved);
    EXPECT_EQ(f.state.selected_material, 3);
    EXPECT_EQ(f.picks, 1);
    // A second click within kDoubleClickSeconds at the same place re-targets the orbit.
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(101.f, 100.f), 1.2);
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, vec2(101.f, 100.f), 1.25);
    EXPECT_TRUE(f.frame_once(act).camera_moved);
    EXPECT_EQ(f.camera.desc().target, vec3(1.f, 2.f, 3.f));
    // A third click is a single click again (the double click consumed the pair), even if quick.
    f.state.selected_material = -1;
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(101.f, 100.f), 1.3);
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, vec2(101.f, 100.f), 1.31);
    f.frame_once(act);
    EXPECT_EQ(f.state.selected_material, 3);
    // Too late for a double click: a single one.
    f.state.selected_material = -1;
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(101.f, 100.f), 1.3 + Navigation::kDoubleClickSeconds + 0.01);
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, vec2(101.f, 100.f), 1.3 + Navigation::kDoubleClickSeconds + 0.02);
    EXPECT_FALSE(f.frame_once(act).camera_moved);
    EXPECT_EQ(f.state.selected_material, 3);
}

TEST(ViewerNavigation, PickFocusClickSetsTheFocusPlaneOnce) {
    NavFixture f;
    PanelActions act;
    f.state.pick_focus = true;
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, vec2(100.f, 100.f), 0.0);
    f.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, vec2(100.f, 100.f), 0.01);
    EXPECT_TRUE(f.frame_once(act).camera_moved);
    EXPECT_FALSE(f.state.pick_focus);
    EXPECT_GT(f.camera.desc().focus_distance, 0.f);
    EXPECT_EQ(f.state.selected_material, -1);  // focusing selects nothing
}

TEST(ViewerNavigation, WheelDollyOnlyOverTheImage) {
    NavFixture f;
    PanelActions act;
    f.input.scroll = 1.f;
    f.frame.cursor = vec2(500.f, 10.f);  // over the panel
    EXPECT_FALSE(f.frame_once(act).camera_moved);
    EXPECT_EQ(f.input.scroll, 0.f);  // consumed anyway
    f.input.scroll = 1.f;
    f.frame.cursor = vec2(200.f, 150.f);
    EXPECT_TRUE(f.frame_once(act).camera_moved);
    EXPECT_LT(glm::length(f.camera.desc().eye - f.camera.desc().target), 10.f);
}

TEST(ViewerNavigation, ShortcutsRespectImGuiKeyboardFocus) {
    NavFixture f;
    PanelActions act;
    f.frame.imgui_wants_keyboard = true;
    f.input.keys = {{GLFW_KEY_F, 0}, {GLFW_KEY_P, 0}, {GLFW_KEY_S, GLFW_MOD_CONTROL}};
    NavigationResult r = f.frame_once(act);
    EXPECT_TRUE(act.save);  // Ctrl+S works while typing
    EXPECT_FALSE(act.frame_all);
    EXPECT_FALSE(f.state.paused);
    EXPECT_FALSE(r.quit);
    EXPECT_TRUE(f.input.keys.empty());
    f.frame.imgui_wants_keyboard = false;
    PanelActions act2;
    f.input.keys = {{GLFW_KEY_P, 0}, {GLFW_KEY_R, 0}, {GLFW_KEY_Q, GLFW_MOD_CONTROL}};
    r = f.frame_once(act2);
    EXPECT_TRUE(f.state.paused);
    EXPECT_TRUE(act2.control_changed);
    EXPECT_TRUE(act2.reset_camera);
    EXPECT_TRUE(r.quit);
}

// The display is denoised by default; N shows the raw accumulation and back, never while ImGui is typing, and is a
// display change only (no restart).
TEST(ViewerNavigation, NTogglesTheRawAccumulation) {
    NavFixture f;
    EXPECT_TRUE(f.state.display.denoise);
    PanelActions act;
    f.input.keys = {{GLFW_KEY_N, 0}};
    EXPECT_FALSE(f.frame_once(act).camera_moved);
    EXPECT_FALSE(f.state.display.denoise);
    EXPECT_EQ(restart_reason(act, false, false), "");
    f.frame.imgui_wants_keyboard = true;
    f.input.keys = {{GLFW_KEY_N, 0}};
    f.frame_once(act);
    EXPECT_FALSE(f.state.display.denoise);
    f.frame.imgui_wants_keyboard = false;
    f.input.keys = {{GLFW_KEY_N, 0}};
    f.frame_once(act);
    EXPECT_TRUE(f.state.display.denoise);
}

// The panel always says which image is on screen.
TEST(ViewerPanel, SaysWhetherTheDenoisedOrTheRawImageIsShown) {
    ViewState state;
    Snapshot s;
    s.spp = 9;
    EXPECT_EQ(shown_image(state, &s), "RAW (denoising...)");
    s.denoised.assign(3, 0.f);
    s.denoised_spp = 8;
    EXPECT_EQ(shown_image(state, &s), "DENOISED at 8/9 spp");
    s.denoised_nfor = true;  // once rendering stopped
    EXPECT_EQ(shown_image(state, &s), "DENOISED (NFOR) at 8/9 spp");
    s.denoised_nfor = false;
    state.display.denoise = false;
    EXPECT_EQ(shown_image(state, &s), "RAW");
    state.display.view = View::RelativeError;
    EXPECT_EQ(shown_image(state, &s), "false colour (raw)");
}

TEST(ViewerNavigation, HeldFlyKeysMoveByElapsedTime) {
    NavFixture f;
    PanelActions act;
    f.camera.fly_speed = 2.f;
    f.input.fly_down[0] = true;  // W: forward
    f.frame.dt = 0.5;
    EXPECT_TRUE(f.frame_once(act).camera_moved);
    EXPECT_NEAR(f.camera.desc().eye.z, 9.f, 1e-5f);
    f.frame.dt = 0.0;  // the first frame has no elapsed time: no move
    EXPECT_FALSE(f.frame_once(act).camera_moved);
    EXPECT_TRUE(f.input.fly_down[0]);  // held state is not consumed
}

TEST(ViewerRefinement, RestartsCoarseAndRefinesAtRest) {
    RefinementSchedule s;
    auto r = s.coarse("initial", 0.0);
    EXPECT_EQ(s.level(), RefinementSchedule::kCoarsestLevel);
    s.posted(1, r, 0.0);
    // The first pass has not landed: no refinement however long we wait.
    EXPECT_FALSE(s.update("", 5.0, 5.0, 0, 0));
    // Landed, but not yet at rest.
    s.posted(2, *s.update("camera", 0.0, 0.0, 1, 1), 0.0);  // shown 1 of posted 1: not in flight, no deferral
    EXPECT_FALSE(s.update("", RefinementSchedule::kRestSeconds / 2, 0.0, 2, 1));
    // At rest and shown: 4 -> 2 -> 1, then nothing more.
    double t = 1.0;
    auto refine = s.update("", t, t, 2, 1);
    ASSERT_TRUE(refine);
    EXPECT_EQ(refine->reason, "refine");
    EXPECT_EQ(s.level(), 2);
    s.posted(3, *refine, t);
    EXPECT_FALSE(s.update("", t + 1.0, t + 1.0, 2, 5));  // the shown pass is of an older request
    refine = s.update("", t + 1.0, t + 1.0, 3, 1);
    ASSERT_TRUE(refine);
    EXPECT_EQ(s.level(), 1);
    s.posted(4, *refine, t + 1.0);
    EXPECT_FALSE(s.update("", t + 9.0, t + 9.0, 4, 100));
    EXPECT_EQ(s.level(), 1);
}

// The first pass's divisor: the finest of 2, 4, 8, 16 whose predicted time (time per pixel x the pixels at that
// level) fits the budget; 16 when none fits; 4 while nothing is measured.
TEST(ViewerRefinement, CoarseLevelIsTheFinestThatFitsTheBudget) {
    const double full = 640.0 * 480.0, budget = 0.012;
    auto level = [&](double full_frame_seconds) {
        return RefinementSchedule::choose_coarse_level(full_frame_seconds / full, full, budget);
    };
    EXPECT_EQ(RefinementSchedule::choose_coarse_level(0.0, full, budget), RefinementSchedule::kCoarsestLevel);
    EXPECT_EQ(RefinementSchedule::choose_coarse_level(-1.0, full, budget), RefinementSchedule::kCoarsestLevel);
    EXPECT_EQ(level(0.001), 2);             // never full resolution: the refinement follows at rest
    EXPECT_EQ(level(4.0 * budget), 2);      // 1/2: a quarter of the pixels, exactly the budget
    EXPECT_EQ(level(4.1 * budget), 4);      // just over at 1/2
    EXPECT_EQ(level(16.0 * budget), 4);     // 1/4: a sixteenth
    EXPECT_EQ(level(16.1 * budget), 8);     // just over at 1/4
    EXPECT_EQ(level(64.0 * budget), 8);     // 1/8: a sixty-fourth
    EXPECT_EQ(level(64.1 * budget), 16);    // just over at 1/8 (Sponza at 640x480 on two cores)
    EXPECT_EQ(level(1000.0 * budget), 16);  // nothing fits: the coarsest
    // Monotone: a slower scene never gets a finer first pass.
    int last = 2;
    for (double t = 0.001; t < 2.0; t *= 1.1) {
        const int l = level(t);
        EXPECT_GE(l, last) << t;
        last = l;
    }
}

TEST(ViewerRefinement, MeasuredPassTimesSetWhereTheNextChangeRestarts) {
    RefinementSchedule s;
    EXPECT_EQ(s.coarse("initial", 0.0).reason, "initial");
    EXPECT_EQ(s.level(), RefinementSchedule::kCoarsestLevel);  // nothing measured yet
    // 50 ms for 160x120: 2.6 us a pixel, 200 ms at 1/4 of 640x480, 50 ms at 1/8, 12.5 ms at 1/16: the coarsest.
    s.measured_first_pass(0.05, 160 * 120, 640.0 * 480.0, 0.012);
    EXPECT_EQ(s.coarse_level(), 16);
    // 40 ms for 160x120: 10 ms at 1/8, which fits.
    s.measured_first_pass(0.04, 160 * 120, 640.0 * 480.0, 0.012);
    EXPECT_EQ(s.coarse_level(), 8);
    s.posted(1, s.coarse("scene", 0.0), 0.0);
    EXPECT_EQ(s.level(), 8);
    // Refinement halves from there: 8 -> 4 -> 2 -> 1.
    s.posted(2, *s.update("", 1.0, 1.0, 1, 1), 1.0);
    EXPECT_EQ(s.level(), 4);
    // A camera move restarts at the measured level, deferred while its coarse pass is in flight.
    s.measured_first_pass(0.002, 320 * 240, 640.0 * 480.0, 0.012);  // fast: 1/2 fits
    const auto r = s.update("camera", 1.05, 1.05, 1, 1);
    ASSERT_TRUE(r);
    EXPECT_EQ(s.level(), 2);
    s.posted(3, *r, 1.05);
    EXPECT_FALSE(s.update("camera", 1.06, 1.06, 2, 1));  // the 1/2 pass in flight: deferred
    EXPECT_TRUE(s.deferred());
    // A bad measurement (nothing rendered) changes nothing; a new scene starts unmeasured.
    s.measured_first_pass(0.0, 0, 640.0 * 480.0, 0.012);
    EXPECT_EQ(s.coarse_level(), 2);
    s.reset();
    EXPECT_EQ(s.coarse_level(), RefinementSchedule::kCoarsestLevel);
}

TEST(ViewerRefinement, CameraMoveWaitsForTheCoarsePassInFlight) {
    RefinementSchedule s;
    s.posted(1, s.coarse("initial", 0.0), 0.0);
    // The coarse pass of generation 1 is in flight (nothing shown yet): a camera move is deferred.
    EXPECT_FALSE(s.update("camera", 0.05, 0.04, 0, 0));
    EXPECT_TRUE(s.deferred());
    EXPECT_FALSE(s.update("camera", 0.06, 0.06, 0, 0));
    EXPECT_NEAR(s.wait_timeout(0.5, 0.5), RefinementSchedule::kMaxDeferSeconds - 0.5, 1e-12);
    // The pass lands: the move is posted, its latency counted from the first deferred event.
    const auto r = s.update("", 0.1, 0.1, 1, 1);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->reason, "camera");
    EXPECT_DOUBLE_EQ(r->since, 0.04);
    EXPECT_FALSE(s.deferred());
    EXPECT_EQ(s.wait_timeout(0.2, 0.5), 0.5);
}

TEST(ViewerRefinement, DeferralEndsAfterMaxDeferAndOtherChangesNeverWait) {
    RefinementSchedule s;
    s.posted(1, s.coarse("initial", 0.0), 0.0);
    EXPECT_FALSE(s.update("camera", 0.1, 0.1, 0, 0));
    EXPECT_FALSE(s.deferral_expired(0.5));
    EXPECT_TRUE(s.deferral_expired(RefinementSchedule::kMaxDeferSeconds));
    // The pass never landed, but the wait is over: the move goes out.
    const auto r = s.update("", RefinementSchedule::kMaxDeferSeconds + 0.01, 1.0, 0, 0);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->reason, "camera");
    s.posted(2, *r, RefinementSchedule::kMaxDeferSeconds + 0.01);
    // A material edit (or camera plus anything) is posted at once, pass in flight or not.
    const auto m = s.update("camera,material", 1.1, 1.1, 1, 1);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->reason, "camera,material");
}

TEST(ViewerRefinement, CameraMoveAtAFinerLevelRestartsAtOnce) {
    RefinementSchedule s;
    s.posted(1, s.coarse("initial", 0.0), 0.0);
    s.posted(2, *s.update("", 1.0, 1.0, 1, 1), 1.0);  // refined to 1/2, its pass in flight
    EXPECT_EQ(s.level(), 2);
    const auto r = s.update("camera", 1.05, 1.05, 1, 1);
    ASSERT_TRUE(r);
    EXPECT_EQ(s.level(), RefinementSchedule::kCoarsestLevel);
}

TEST(ViewerRefinement, ShownFramesCompletePendingRequestsInOrder) {
    RefinementSchedule s;
    s.posted(1, {"initial", 0.0}, 0.0);
    s.posted(2, {"camera", 0.5}, 0.6);
    s.posted(3, {"camera", 0.7}, 0.8);
    EXPECT_TRUE(s.shown(0).empty());
    const auto done = s.shown(2);
    ASSERT_EQ(done.size(), 2u);
    EXPECT_EQ(done[0].generation, 1u);
    EXPECT_EQ(done[1].reason, "camera");
    EXPECT_DOUBLE_EQ(done[1].since, 0.5);
    s.reset();  // a new renderer: nothing pending, generations from 1 again
    EXPECT_TRUE(s.shown(99).empty());
    EXPECT_EQ(s.posted_generation(), 0u);
}

namespace {
// Waits until the loader's job has ended; the deadline (300 s, for a loaded sanitizer build) catches a hang only.
bool wait_ready(const SceneLoader& loader) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
    while (!loader.ready() && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return loader.ready();
}
}  // namespace

TEST(ViewerSceneLoader, LoadsOffThreadAndWakesOnce) {
    std::atomic<int> wakes{0};
    SceneLoader loader([&] { ++wakes; });
    EXPECT_FALSE(loader.busy());
    ASSERT_TRUE(loader.start([] { return load_scene(builtin_scene_path()); }, 1));
    EXPECT_FALSE(loader.start([] { return Scene{}; }, 1));  // one load at a time
    ASSERT_TRUE(wait_ready(loader));
    LoadedScene loaded = loader.take();
    ASSERT_TRUE(loaded.scene && loaded.renderer);
    EXPECT_GT(loaded.scene->triangle_count(), 0u);
    EXPECT_EQ(wakes.load(), 1);
    EXPECT_FALSE(loader.busy());
}

TEST(ViewerSceneLoader, ErrorsReachTheTakerAndStillWake) {
    std::atomic<int> wakes{0};
    SceneLoader loader([&] { ++wakes; });
    ASSERT_TRUE(loader.start([]() -> Scene { throw Error("missing.obj: cannot open"); }, 1));
    ASSERT_TRUE(wait_ready(loader));
    EXPECT_THROW(loader.take(), Error);
    EXPECT_EQ(wakes.load(), 1);
    EXPECT_TRUE(loader.start([] { return load_scene(builtin_scene_path()); }, 1));  // usable again
    loader.wait();
}

}  // namespace pv::ui

// The Light section's live mix (ui/light_mix.h): gains from intensity x colour, mute and solo; the entries follow the
// snapshot's groups and start again at 1 when they change.
TEST(UiLightMix, GainsMuteSoloAndSync) {
    std::vector<pv::ui::LightMixEntry> mix;
    EXPECT_TRUE(pv::ui::sync_light_mix(mix, {"lamp", "sky", "sun"}));
    EXPECT_FALSE(pv::ui::sync_light_mix(mix, {"lamp", "sky", "sun"}));
    EXPECT_EQ(pv::ui::light_mix_gains(mix), pv::LightGains(3, pv::vec3(1.f)));
    mix[0].intensity = 2.f;
    mix[0].colour = pv::vec3(1.f, 0.5f, 0.25f);
    mix[2].mute = true;
    EXPECT_EQ(pv::ui::light_mix_gains(mix), (pv::LightGains{pv::vec3(2.f, 1.f, 0.5f), pv::vec3(1.f), pv::vec3(0.f)}));
    mix[1].solo = true;
    EXPECT_EQ(pv::ui::light_mix_gains(mix), (pv::LightGains{pv::vec3(0.f), pv::vec3(1.f), pv::vec3(0.f)}));
    EXPECT_TRUE(pv::ui::sync_light_mix(mix, {"lamp", "sky"}));
    EXPECT_EQ(pv::ui::light_mix_gains(mix), pv::LightGains(2, pv::vec3(1.f)));
}
