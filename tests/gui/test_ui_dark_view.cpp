// tests/gui/test_ui_dark_view.cpp: the viewer's dark-view hint (ui/dark_view.h): a snapshot that reads as dark while
// no sky or sun lights the scene raises it, a lit environment or a bright image does not, nor does an empty
// snapshot; the hint's "default sky" rebuilds the current scene with the default sky in the background (the view and
// materials kept), refused during another load.
#include <gtest/gtest.h>

#include "core/image/metrics.h"
#include "core/load/scene_file.h"
#include "core/scene/environment.h"
#include "dark_view.h"
#include "scene_loads.h"

namespace pv::ui {
namespace {

Snapshot uniform(float v, uint64_t serial, uint32_t spp = 1) {
    Snapshot s;
    s.generation = 1;
    s.serial = serial;
    s.width = 4;
    s.height = 2;
    s.spp = spp;
    s.rgb.assign(24, v);
    return s;
}

TEST(ViewerDarkView, DarkOnlyWithoutEnvironmentLightAndBelowTheBound) {
    DarkView d;
    EXPECT_FALSE(d.update(uniform(0.f, 1, 0), false)) << "nothing rendered yet";
    const float below = float(kDarkMeanLuminance) * 0.9f, above = float(kDarkMeanLuminance) * 1.1f;
    EXPECT_TRUE(d.update(uniform(below, 2), false));
    EXPECT_NEAR(d.mean(), double(below), 1e-6);
    EXPECT_FALSE(d.update(uniform(below, 2), true)) << "a sky or sun lights it: not the scene's own lights' fault";
    EXPECT_FALSE(d.update(uniform(above, 3), false));
    // A very bright pixel (a visible lamp) counts as white, not as its radiance: one of eight gives 1/8.
    Snapshot lamp = uniform(0.f, 4);
    lamp.rgb[0] = lamp.rgb[1] = lamp.rgb[2] = 1e4f;
    EXPECT_FALSE(d.update(lamp, false));
    EXPECT_NEAR(d.mean(), 1.0 / 8.0, 1e-6);
    // Measured once per snapshot: the same serial keeps the measure.
    EXPECT_FALSE(d.update(lamp, false));
}

TEST(ViewerDarkView, DefaultSkyRebuildsTheSceneWithItAndIsRefusedDuringALoad) {
    ViewLog log("");
    ActiveScene scene(log);
    SceneLoader loader([] {});
    SceneLoads loads(loader, scene, log, 1);
    ViewState state;
    const CameraDesc camera{vec3(0.f, 0.f, 5.f), vec3(0.f), vec3(0.f, 1.f, 0.f), 40.f};
    state.scene_path = builtin_scene_path();
    loads.load(state);
    loader.wait();
    loads.environment("sky", state, camera);  // the load has ended but is not taken: one at a time
    EXPECT_FALSE(state.drop_ok);
    EXPECT_EQ(state.drop_status, "environment sky: not added, a load is running; try again when it ends");
    std::optional<LoadedScene> first = loads.take_finished(state);
    ASSERT_TRUE(first.has_value());
    scene.adopt(first->scene, state);
    loads.adopted(state);
    EXPECT_FALSE(environment_emits(scene.scene(), state.environment)) << "the Cornell box has no sky";

    loads.environment("sky", state, camera);
    EXPECT_TRUE(state.drop_ok) << state.drop_status;
    loader.wait();
    std::optional<LoadedScene> lit = loads.take_finished(state);
    ASSERT_TRUE(lit.has_value());
    EXPECT_NE(lit->scene->environment_map, kNoIndex);
    EXPECT_EQ(lit->scene->triangle_count(), first->scene->triangle_count());
    scene.adopt(lit->scene, state);
    loads.adopted(state);
    EXPECT_TRUE(environment_emits(scene.scene(), state.environment));
    EXPECT_TRUE(state.drop_ok);
}

}  // namespace
}  // namespace pv::ui
