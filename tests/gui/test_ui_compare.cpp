// tests/gui/test_ui_compare.cpp: the compare room (compare.h: holding B, loading it from an EXR, relMSE against it,
// the difference image, the views and the divider) and the gestures that drive it (navigation.h). No display.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "compare.h"
#include "core/image/image_io.h"
#include "core/image/metrics.h"
#include "navigation.h"
#include "tests/support/temp_dir.h"

namespace pv::ui {
namespace {

CameraDesc camera_at(float z) { return CameraDesc{vec3(0.f, 0.f, z), vec3(0.f), vec3(0.f, 1.f, 0.f), 40.f}; }

// A w x h snapshot of constant radiance v (and a denoised image of constant d when d >= 0).
Snapshot constant(int w, int h, float v, float d = -1.f, uint64_t generation = 1, double seconds = 1.0) {
    Snapshot s;
    s.generation = generation;
    s.width = w;
    s.height = h;
    s.rgb.assign(size_t(w) * size_t(h) * 3, v);
    if (d >= 0.f) {
        s.denoised.assign(s.rgb.size(), d);
        s.denoised_spp = 4;
    }
    s.spp = 8;
    s.paths = uint64_t(w) * uint64_t(h) * 8;
    s.seconds = seconds;
    return s;
}

Image constant_image(int w, int h, float v) {
    Image img(w, h);
    std::fill(img.rgb.begin(), img.rgb.end(), v);
    return img;
}

}  // namespace

// Holding copies the colour shown (the denoised image when it is shown), opens the split view, and remembers the
// camera: the same camera is no move, another one is.
TEST(ViewerCompare, HoldKeepsTheShownImageAndItsCamera) {
    Compare c;
    EXPECT_FALSE(c.has_b());
    EXPECT_EQ(c.view(), CompareView::Off);
    const Snapshot s = constant(4, 3, 0.5f, 0.25f);
    c.hold(s, false, camera_at(10.f));
    ASSERT_TRUE(c.has_b());
    EXPECT_TRUE(c.ok());
    EXPECT_EQ(c.b().width, 4);
    EXPECT_EQ(c.b().height, 3);
    EXPECT_EQ(c.b().rgb, s.rgb);
    EXPECT_EQ(c.view(), CompareView::Split);
    EXPECT_FALSE(c.camera_moved(camera_at(10.f)));
    EXPECT_TRUE(c.camera_moved(camera_at(11.f)));
    CameraDesc fov = camera_at(10.f);
    fov.vfov_deg = 41.f;
    EXPECT_TRUE(c.camera_moved(fov));
    c.hold(s, true, camera_at(11.f));  // denoised shown: B is the denoised image
    EXPECT_EQ(c.b().rgb, s.denoised);
    EXPECT_FALSE(c.camera_moved(camera_at(11.f)));
    EXPECT_NE(c.source().find("denoised"), std::string::npos) << c.source();
}

TEST(ViewerCompare, HoldingNothingRenderedKeepsBAndSaysSo) {
    Compare c;
    c.hold(Snapshot{}, false, camera_at(10.f));
    EXPECT_FALSE(c.has_b());
    EXPECT_FALSE(c.ok());
    EXPECT_EQ(c.status(), "nothing rendered yet to hold as B");
    c.hold(constant(2, 2, 1.f), false, camera_at(10.f));
    c.hold(Snapshot{}, false, camera_at(10.f));
    EXPECT_TRUE(c.has_b());  // the earlier B stays
    EXPECT_EQ(c.b().width, 2);
}

// An EXR of the image's size becomes B (with no camera: never "moved"); a wrong-size or unreadable one leaves B as it
// was and says so in one line naming the file.
TEST(ViewerCompare, LoadChecksTheFileAndItsSize) {
    const test::TestDir dir("pathview-compare");
    const std::string good = (dir.path / "ref.exr").string();
    const std::string small = (dir.path / "small.exr").string();
    const std::string junk = (dir.path / "junk.exr").string();
    write_exr(good, constant_image(4, 3, 0.75f));
    write_exr(small, constant_image(2, 3, 0.75f));
    { std::ofstream(junk) << "not an exr"; }
    Compare c;
    EXPECT_TRUE(c.load(good, 4, 3));
    ASSERT_TRUE(c.has_b());
    EXPECT_TRUE(c.from_file());
    EXPECT_EQ(c.source(), good);
    EXPECT_EQ(c.b().rgb, constant_image(4, 3, 0.75f).rgb);
    EXPECT_FALSE(c.camera_moved(camera_at(99.f)));
    EXPECT_EQ(c.view(), CompareView::Split);

    EXPECT_FALSE(c.load(small, 4, 3));
    EXPECT_FALSE(c.ok());
    EXPECT_EQ(c.status(), small + ": 2x3 pixels; expected the image's 4x3");
    EXPECT_EQ(c.source(), good);  // B unchanged
    for (const std::string& bad : {junk, (dir.path / "missing.exr").string()}) {
        EXPECT_FALSE(c.load(bad, 4, 3));
        EXPECT_FALSE(c.ok());
        EXPECT_EQ(c.status().rfind(bad, 0), 0u) << c.status();  // starts with the file's name
        EXPECT_EQ(c.status().find('\n'), std::string::npos);
        EXPECT_EQ(c.source(), good);
    }
}

// relMSE of the raw mean (and the denoised image) against B, as core/image/metrics.h defines it: for constants a and b,
// (a - b)^2 / (b^2 + 0.01). Only at B's size; the history follows the accumulation.
TEST(ViewerCompare, RelMseAgainstBAndItsHistory) {
    Compare c;
    c.set_b(constant_image(4, 3, 1.f), "ref.exr");
    c.update(constant(4, 3, 1.1f, 1.05f, 1, 1.0));
    ASSERT_TRUE(c.rel_mse());
    const double expected = 0.1 * 0.1 / (1.0 + kMetricEps);
    EXPECT_NEAR(*c.rel_mse(), expected, 1e-6 * expected);
    EXPECT_NEAR(c.rel_mse_denoised(), 0.05 * 0.05 / (1.0 + kMetricEps), 1e-5 * expected);
    EXPECT_EQ(c.history().size(), 1u);
    Snapshot later = constant(4, 3, 1.05f, -1.f, 1, 2.0);
    later.spp = 16;
    later.paths *= 2;
    c.update(later);
    EXPECT_LT(c.rel_mse_denoised(), 0.0);  // no denoised image
    EXPECT_EQ(c.history().size(), 2u);
    float lo = 0.f, hi = 0.f;
    const std::vector<float> plot = c.history().log_log_by_seconds(8, lo, hi);
    ASSERT_EQ(plot.size(), 8u);
    EXPECT_NEAR(plot.front(), std::log10(expected), 1e-4);
    EXPECT_NEAR(plot.back(), std::log10(0.05 * 0.05 / (1.0 + kMetricEps)), 1e-3);
    // A coarse pass (another size): no relMSE; a new accumulation starts a new history.
    c.update(constant(2, 1, 1.1f, -1.f, 2));
    EXPECT_FALSE(c.rel_mse());
    c.update(constant(4, 3, 1.1f, -1.f, 3));
    EXPECT_EQ(c.history().size(), 1u);
    c.clear();
    c.update(constant(4, 3, 1.1f));
    EXPECT_FALSE(c.rel_mse());
}

// |A - B| / (B + 0.01) per pixel, averaged over channels, at A's size with B sampled at the nearest pixel.
TEST(ViewerCompare, DifferenceIsRelativeToBAtTheSizeOfA) {
    Compare c;
    EXPECT_TRUE(c.difference(constant(2, 2, 1.f).rgb.data(), 2, 2).empty());  // no B
    Image b(2, 1);
    b.set(0, 0, vec3(1.f));
    b.set(1, 0, vec3(0.f, 2.f, 4.f));
    c.set_b(b, "b");
    Snapshot a = constant(4, 2, 2.f);
    const std::vector<float> d = c.difference(a.rgb.data(), 4, 2);
    ASSERT_EQ(d.size(), 8u);
    const float left = 1.f / 1.01f;
    const float right = (2.f / 0.01f + 0.f / 2.01f + 2.f / 4.01f) / 3.f;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x)
            EXPECT_NEAR(d[size_t(y) * 4 + size_t(x)], x < 2 ? left : right, 1e-5f * (x < 2 ? left : right))
                << x << "," << y;
    c.set_b(constant_image(4, 2, 2.f), "same");
    for (float v : c.difference(a.rgb.data(), 4, 2)) EXPECT_EQ(v, 0.f);
}

// C cycles A -> split -> difference -> A; V flips to B and back to the view before; the divider clamps to the
// image and brings up the split view; without B every view is A.
TEST(ViewerCompare, ViewsFlipAndDivider) {
    Compare c;
    const Snapshot s = constant(2, 2, 1.f);
    CompareActions cycle;
    cycle.cycle = true;
    EXPECT_FALSE(c.apply(CompareActions{}, s, false, camera_at(1.f), 2, 2));
    c.apply(cycle, s, false, camera_at(1.f), 2, 2);
    EXPECT_EQ(c.view(), CompareView::Off);  // nothing held
    CompareActions hold;
    hold.hold = true;
    EXPECT_TRUE(c.apply(hold, s, false, camera_at(1.f), 2, 2));
    EXPECT_EQ(c.view(), CompareView::Split);
    EXPECT_TRUE(c.apply(cycle, s, false, camera_at(1.f), 2, 2));
    EXPECT_EQ(c.view(), CompareView::Difference);
    CompareActions flip;
    flip.flip = true;
    c.apply(flip, s, false, camera_at(1.f), 2, 2);
    EXPECT_EQ(c.view(), CompareView::ShowB);
    c.apply(flip, s, false, camera_at(1.f), 2, 2);
    EXPECT_EQ(c.view(), CompareView::Difference);
    c.apply(cycle, s, false, camera_at(1.f), 2, 2);
    EXPECT_EQ(c.view(), CompareView::Off);
    CompareActions drag;
    drag.divider = 1.7f;
    EXPECT_TRUE(c.apply(drag, s, false, camera_at(1.f), 2, 2));
    EXPECT_EQ(c.divider(), 1.f);
    EXPECT_EQ(c.view(), CompareView::Split);
    drag.divider = 0.25f;
    c.apply(drag, s, false, camera_at(1.f), 2, 2);
    EXPECT_EQ(c.divider(), 0.25f);
    EXPECT_FALSE(c.apply(drag, s, false, camera_at(1.f), 2, 2));  // no change
    CompareActions clear;
    clear.clear = true;
    EXPECT_TRUE(c.apply(clear, s, false, camera_at(1.f), 2, 2));
    EXPECT_FALSE(c.has_b());
    EXPECT_EQ(c.view(), CompareView::Off);
}

// Keys B, C, V ask the compare room to hold, cycle and flip; a right drag moves the divider to the cursor's fraction
// of the image width without moving the camera or picking; none of it while ImGui has the keyboard or mouse.
TEST(ViewerNavigation, CompareKeysAndRightDragDivider) {
    ViewLog log("");
    Navigation nav(log);
    CameraController camera(camera_at(10.f), vec3(-1.f), vec3(1.f));
    ViewState state;
    InputQueue input;
    NavigationFrame frame;
    frame.image_size = vec2(400.f, 300.f);
    frame.window_height = 300;
    int picks = 0;
    frame.pick = [&](vec2) {
        ++picks;
        return std::optional<PickResult>();
    };
    PanelActions act;
    input.keys = {{GLFW_KEY_B, 0}, {GLFW_KEY_C, 0}, {GLFW_KEY_V, 0}};
    nav.handle(input, frame, camera, state, act);
    EXPECT_TRUE(act.compare.hold);
    EXPECT_TRUE(act.compare.cycle);
    EXPECT_TRUE(act.compare.flip);
    PanelActions typing;
    frame.imgui_wants_keyboard = true;
    input.keys = {{GLFW_KEY_B, 0}, {GLFW_KEY_C, 0}, {GLFW_KEY_V, 0}};
    nav.handle(input, frame, camera, state, typing);
    EXPECT_FALSE(typing.compare.hold || typing.compare.cycle || typing.compare.flip);
    frame.imgui_wants_keyboard = false;

    const CameraDesc before = camera.desc();
    PanelActions drag;
    input.buttons.push_back({GLFW_MOUSE_BUTTON_RIGHT, GLFW_PRESS, 0, vec2(100.f, 50.f), 0.0});
    frame.cursor = vec2(300.f, 80.f);
    EXPECT_FALSE(nav.handle(input, frame, camera, state, drag).camera_moved);
    ASSERT_TRUE(drag.compare.divider);
    EXPECT_FLOAT_EQ(*drag.compare.divider, 0.75f);
    PanelActions release;
    input.buttons.push_back({GLFW_MOUSE_BUTTON_RIGHT, GLFW_RELEASE, 0, vec2(500.f, 80.f), 0.1});
    EXPECT_FALSE(nav.handle(input, frame, camera, state, release).camera_moved);
    ASSERT_TRUE(release.compare.divider);
    EXPECT_FLOAT_EQ(*release.compare.divider, 1.f);  // past the image's edge: clamped
    EXPECT_EQ(camera.desc().eye, before.eye);
    EXPECT_EQ(picks, 0);
    EXPECT_FALSE(state.region);
    PanelActions over_panel;
    frame.imgui_wants_mouse = true;
    input.buttons.push_back({GLFW_MOUSE_BUTTON_RIGHT, GLFW_PRESS, 0, vec2(100.f, 50.f), 1.0});
    nav.handle(input, frame, camera, state, over_panel);
    EXPECT_FALSE(over_panel.compare.divider);
}

}  // namespace pv::ui
