// tests/frame/test_smoke.cpp: the built-in Cornell box loads and renders a finite image.
// Test kinds: unit
#include <gtest/gtest.h>

#include "core/frame/renderer.h"
#include "core/load/scene_file.h"
#include "tests/support/scenes.h"

namespace pv {

TEST(Smoke, CornellBoxRendersFiniteImage) {
    auto scene = std::make_shared<Scene>(load_scene(builtin_scene_path()));
    EXPECT_EQ(scene->triangle_count(), 32u);
    Renderer r(scene, 2);
    r.restart(scene->camera, RenderSettings{}, 32, 32);
    ASSERT_TRUE(r.render_pass());
    test::expect_finite_and_lit(r.film().mean());
    EXPECT_EQ(r.stats().dropped, 0u);
}

}  // namespace pv
