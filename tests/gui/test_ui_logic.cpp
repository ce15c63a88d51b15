// tests/gui/test_ui_logic.cpp: the viewer's window-free logic: camera navigation and the convergence history.
// Built only with the UI (it links pathview_ui); needs no display.
#include <gtest/gtest.h>

#include <cmath>

#include "camera_controller.h"
#include "convergence.h"
#include "shown_image.h"

namespace pv::ui {
namespace {

// Eye on +z at distance 10 from the origin, y up, 40 degrees.
CameraDesc test_camera() { return CameraDesc{vec3(0.f, 0.f, 10.f), vec3(0.f), vec3(0.f, 1.f, 0.f), 40.f}; }

CameraController controller() { return CameraController(test_camera(), vec3(-1.f), vec3(1.f)); }

float distance(const CameraDesc& c) { return glm::length(c.eye - c.target); }

}  // namespace

TEST(ViewerCamera, OrbitKeepsTargetAndDistance) {
    CameraController cam = controller();
    cam.orbit(vec2(120.f, -80.f));
    EXPECT_EQ(cam.desc().target, vec3(0.f));
    EXPECT_NEAR(distance(cam.desc()), 10.f, 1e-4f);
    EXPECT_GT(std::fabs(cam.desc().eye.x), 1.f);  // a horizontal drag turns about the up axis
}

TEST(ViewerCamera, OrbitStopsShortOfThePoles) {
    CameraController cam = controller();
    cam.orbit(vec2(0.f, 5000.f));  // far past straight down
    const vec3 dir = glm::normalize(cam.desc().eye - cam.desc().target);
    EXPECT_LT(std::fabs(glm::dot(dir, vec3(0.f, 1.f, 0.f))), 1.f - 1e-5f);
    EXPECT_TRUE(is_finite(cam.desc().eye));
}

TEST(ViewerCamera, PanMovesEyeAndTargetTogether) {
    CameraController cam = controller();
    cam.pan(vec2(100.f, 0.f), 500);
    const CameraDesc& c = cam.desc();
    EXPECT_NEAR(c.target.x, c.eye.x, 1e-4f);  // both moved by the same amount
    EXPECT_LT(c.target.x, 0.f);               // dragging right moves the view left
    // One image height of drag spans the view at the target: 2 d tan(fov/2).
    const float expected = 100.f / 500.f * 2.f * 10.f * std::tan(glm::radians(20.f));
    EXPECT_NEAR(-c.target.x, expected, 1e-4f);
    EXPECT_NEAR(distance(c), 10.f, 1e-4f);
}

TEST(ViewerCamera, DollyScalesDistanceAndClamps) {
    CameraController cam = controller();
    cam.dolly(1.f);
    EXPECT_NEAR(distance(cam.desc()), 8.5f, 1e-4f);
    cam.dolly(1000.f);
    EXPECT_GT(distance(cam.desc()), 0.f);
    EXPECT_TRUE(is_finite(cam.desc().eye));
}

TEST(ViewerCamera, FlyFrameAllResetRetargetFocus) {
    CameraController cam = controller();
    cam.fly_speed = 2.f;
    cam.fly(vec3(0.f, 0.f, 1.f), 0.5f);  // forward for half a second
    EXPECT_NEAR(cam.desc().eye.z, 9.f, 1e-5f);
    EXPECT_NEAR(cam.desc().target.z, -1.f, 1e-5f);
    cam.frame_all();
    EXPECT_EQ(cam.desc().target, vec3(0.f));
    const float radius = std::sqrt(3.f);
    EXPECT_NEAR(distance(cam.desc()), radius / std::sin(glm::radians(20.f)) * 1.05f, 1e-3f);
    cam.retarget(vec3(1.f, 0.f, 0.f));
    EXPECT_EQ(cam.desc().target, vec3(1.f, 0.f, 0.f));
    cam.focus_on(vec3(0.f, 5.f, 0.f));
    EXPECT_GT(cam.desc().focus_distance, 0.f);
    cam.reset();
    EXPECT_EQ(cam.desc().eye, test_camera().eye);
    EXPECT_EQ(cam.desc().focus_distance, 0.f);
}

TEST(ViewerCamera, FlagsDescribeTheCamera) {
    CameraDesc c = test_camera();
    c.aperture = 0.25f;
    c.focus_distance = 7.f;
    EXPECT_EQ(camera_flags(c), "--eye 0,0,10 --target 0,0,0 --up 0,1,0 --fov 40 --aperture 0.25 --focus-distance 7");
}

TEST(ViewerConvergence, SlopeAndResampling) {
    ConvergenceHistory h;
    for (uint32_t spp = 1; spp <= 64; ++spp) h.add(spp, 0.1 * spp, 0.5 / spp);  // relMSE ~ 1/spp
    EXPECT_NEAR(h.slope_vs_spp(), -1.0, 1e-9);
    float lo = 0.f, hi = 0.f;
    const std::vector<float> v = h.log_log_by_spp(16, lo, hi);
    ASSERT_EQ(v.size(), 16u);
    EXPECT_NEAR(lo, 0.f, 1e-6f);
    EXPECT_NEAR(hi, std::log10(64.f), 1e-5f);
    EXPECT_NEAR(v.front(), std::log10(0.5f), 1e-5f);
    EXPECT_NEAR(v.back(), std::log10(0.5f / 64.f), 1e-5f);
    for (size_t i = 1; i < v.size(); ++i) EXPECT_LT(v[i], v[i - 1]);
    h.clear();
    h.add(1, 0.1, 0.0);  // below 2 spp there is no estimate
    EXPECT_TRUE(h.log_log_by_seconds(16, lo, hi).empty());
}

// With adaptive sampling a pass samples only part of the image: the slope is taken against the samples taken per
// pixel (paths / pixels), so an unbiased render still shows -1 (against the passes it would show about -0.6 here).
TEST(ViewerConvergence, SlopeFollowsTheSamplesTakenNotThePasses) {
    ShownImage shown;
    const int w = 10, h = 10;
    double samples = 0.0;
    for (uint32_t pass = 1; pass <= 256; ++pass) {
        samples += pass <= 16 ? 1.0 : 0.4;  // from the first checkpoint on, 40% of the pixels each pass
        Snapshot s;
        s.generation = 1;
        s.serial = pass;
        s.width = w;
        s.height = h;
        s.spp = pass;
        s.paths = uint64_t(std::llround(samples * w * h));
        s.seconds = 0.01 * samples;
        s.rel_mse = 0.5 / samples;
        ASSERT_TRUE(shown.update([&](Snapshot& out) {
            out = s;
            return true;
        }));
    }
    EXPECT_NEAR(shown.history().slope_vs_spp(), -1.0, 1e-3);
}

}  // namespace pv::ui
