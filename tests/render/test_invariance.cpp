// tests/render/test_invariance.cpp: the Cornell box renders the same, statistically (per-pixel Welch and the total
// mean, independent seeds), when scaled by 1e-4 .. 1e4 or translated by up to 1e5, camera included.
// Test kinds: statistical
#include <gtest/gtest.h>

#include "core/frame/renderer.h"
#include "tests/support/scenes.h"
#include "tests/support/stats.h"

namespace pv {
namespace {

// ---------------------------------------------------------------- scale and translation invariance

std::shared_ptr<Scene> transformed_cornell(float scale, vec3 translate) {
    auto s = std::make_shared<Scene>(*test::cornell_box());
    for (vec3& p : s->positions) p = p * scale + translate;
    s->camera.eye = s->camera.eye * scale + translate;
    s->camera.target = s->camera.target * scale + translate;
    return s;
}

// Statistically identical images (per-pixel Welch + total mean, independent seeds) for the Cornell box scaled by s
// or translated by T along (1, 0.6, -0.8) (camera included). The asserted range is the required one (s = 1e-4..1e4,
// T up to 1e5). Measured beyond it with the same 16x16, 128 spp comparison (with the scale-free near-origin offset
// and tnear = FLT_MIN): s = 1e-8 .. 1e7 and T = 3e5 .. 1e6 pass; T = 1e7 fails (63 of 768 pixel-channels) at the
// box's edges and corners (a float ULP at 1e7 is 1 unit and the 256-ULP offset 256 units of a 556-unit box), and
// s = 1e8 fails everywhere (210).
TEST(Invariance, CornellBoxUnderScaleAndTranslation) {
    RenderSettings base;
    base.sampler = SamplerKind::Independent;  // bounds below use the i.i.d. sample variance
    base.seed = 500;
    auto scene = test::cornell_box();
    const int w = 16, h = 16, spp = 128;
    const auto ref = test::PixelStats::from_film(test::render_with_renderer(scene, scene->camera, base, w, h, spp));
    struct Variant {
        float s;
        float t;
    };
    const Variant variants[] = {{1e-4f, 0}, {1e-2f, 0}, {1e2f, 0}, {1e4f, 0},
                                {1, 1e2f},  {1, 1e3f},  {1, 1e4f}, {1, 1e5f}};
    uint32_t seed = 501;
    for (const Variant& v : variants) {
        auto s = transformed_cornell(v.s, v.t * vec3(1.f, 0.6f, -0.8f));
        RenderSettings rs = base;
        rs.seed = seed++;
        const auto img = test::PixelStats::from_film(test::render_with_renderer(s, s->camera, rs, w, h, spp));
        const auto c = test::compare_images(ref, img);
        EXPECT_TRUE(c.passed) << "scale " << v.s << ", translation " << v.t << ": " << c.describe();
    }
}

}  // namespace
}  // namespace pv
