// tests/image/test_ocio_view.cpp: OpenColorIO configs and views (core/image/ocio_view.h) with a config the test
// writes: the sRGB view agrees with pathview's own sRGB encoding, the 2.2 gamma view with x^(1/2.2), the baked
// LUT the viewer samples with the processor, and bad configs, displays and views are one-line errors naming the file.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>

#include "core/base/error.h"
#include "core/image/ocio_view.h"
#include "core/image/view_transform.h"
#include "tests/image/ocio_test_config.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(OcioView, ListsDisplaysAndViews) {
    const test::TestDir dir("pv_ocio");
    const auto config = OcioConfig::load(dir.write("config.ocio", test::kOcioTestConfig));
    EXPECT_EQ(config->displays(), (std::vector<std::string>{"sRGB", "Raw"}));
    EXPECT_EQ(config->default_display(), "sRGB");
    EXPECT_EQ(config->views("sRGB"), (std::vector<std::string>{"Standard", "Gamma 2.2"}));
    EXPECT_EQ(config->default_view("sRGB"), "Standard");
    const OcioView v(config, "", "");
    EXPECT_EQ(v.describe(), "sRGB/Standard");
}

TEST(OcioView, StandardViewIsTheSrgbEncoding) {
    const test::TestDir dir("pv_ocio");
    const auto config = OcioConfig::load(dir.write("config.ocio", test::kOcioTestConfig));
    const OcioView srgb(config, "sRGB", "Standard"), gamma(config, "sRGB", "Gamma 2.2");
    std::mt19937 rng(40);
    std::uniform_real_distribution<float> u(-12.f, 0.f);  // the views do not clip above 1: PNG bytes do
    for (int i = 0; i < 2000; ++i) {
        const float x = std::exp2(u(rng));
        float a[3] = {x, x, x}, b[3] = {x, x, x};
        srgb.apply(a, 1);
        gamma.apply(b, 1);
        // OpenColorIO's CPU path evaluates powers with its own fast approximation (relative error ~1e-5 here).
        EXPECT_NEAR(a[0], srgb_encode(x), 3e-5f) << x;
        EXPECT_NEAR(b[0], std::pow(double(x), 1 / 2.2), 3e-5) << x;
    }
    // Whole images: the PNG bytes through OpenColorIO's sRGB view and pathview's clamp agree to a code value.
    Image img(64, 64);
    for (float& v : img.rgb) v = std::exp2(u(rng));
    DisplayTransform clamp, ocio;
    ocio.transform = ViewTransform::Ocio;
    ocio.ocio = std::make_shared<const OcioView>(config, "sRGB", "Standard");
    const std::vector<uint8_t> a = display_bytes(img, clamp), b = display_bytes(img, ocio);
    size_t differ = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_LE(std::abs(int(a[i]) - int(b[i])), 1);
        differ += a[i] != b[i];
    }
    EXPECT_LT(differ, a.size() / 100);  // only values within ~1e-5 of a rounding boundary
}

TEST(OcioView, BakedLutFollowsTheProcessor) {
    const test::TestDir dir("pv_ocio");
    const auto config = OcioConfig::load(dir.write("config.ocio", test::kOcioTestConfig));
    const OcioView view(config, "sRGB", "Standard");
    const std::vector<float> lut = bake_display_lut(view);
    // The shaper: node 0 is 0, node 1 is 2^-14, the last 2^10; monotone in between.
    EXPECT_EQ(lut_coordinate(0.f), 0.f);
    EXPECT_FLOAT_EQ(lut_coordinate(std::exp2(kLutLog2Min)), 1.f);
    EXPECT_FLOAT_EQ(lut_coordinate(std::exp2(kLutLog2Max)), float(kDisplayLutSize - 1));
    EXPECT_FLOAT_EQ(lut_coordinate(1e9f), float(kDisplayLutSize - 1));
    std::mt19937 rng(41);
    std::uniform_real_distribution<float> u(-16.f, 3.f);
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
        const vec3 c(std::exp2(u(rng)), std::exp2(u(rng)), std::exp2(u(rng)));
        float exact[3] = {c.x, c.y, c.z};
        view.apply(exact, 1);
        const vec3 approx = sample_display_lut(lut, kDisplayLutSize, c);
        // What reaches the screen: an 8-bit target clamps to [0, 1].
        for (int k = 0; k < 3; ++k)
            worst = std::max(worst, double(std::abs(glm::clamp(approx[k], 0.f, 1.f) - glm::clamp(exact[k], 0.f, 1.f))));
    }
    // The view is per channel, so trilinear interpolation is linear interpolation along each axis, which over
    // 0.381-stop cells of the sRGB curve in log2 space errs by at most h^2/8 max|f''|: f(u) = 1.055 2^(u/2.4) - 0.055
    // has f'' <= 1.055 (ln2/2.4)^2 = 0.088 below u = 0 (output 1), so 1.6e-3; the linear segment near 0 and the
    // first cell (linear in x) err less. Under half a code value (2e-3).
    EXPECT_LT(worst, 1.7e-3);
    std::printf("largest LUT error %.2e (code values)\n", worst);
}

TEST(OcioView, BadConfigsAndNamesAreOneLineErrors) {
    const test::TestDir dir("pv_ocio");
    const std::string missing = dir.file("missing.ocio");
    std::string e = error_of([&] { OcioConfig::load(missing); });
    EXPECT_TRUE(has(e, missing) && has(e, "OpenColorIO")) << e;
    const std::string junk = dir.write("junk.ocio", "ocio_profile_version: 2\ncolorspaces: [[[\n");
    e = error_of([&] { OcioConfig::load(junk); });
    EXPECT_TRUE(has(e, junk)) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    const auto config = OcioConfig::load(dir.write("config.ocio", test::kOcioTestConfig));
    e = error_of([&] { OcioView(config, "P3", ""); });
    EXPECT_TRUE(has(e, "no display 'P3'") && has(e, "'sRGB', 'Raw'") && has(e, dir.file("config.ocio"))) << e;
    e = error_of([&] { OcioView(config, "sRGB", "Filmic"); });
    EXPECT_TRUE(has(e, "no view 'Filmic'") && has(e, "'Standard', 'Gamma 2.2'")) << e;
    e = error_of([&] { OcioView(config, "", "", "ACEScg"); });
    EXPECT_TRUE(has(e, "'ACEScg'") && has(e, "--ocio-input")) << e;
    // No path and no $OCIO.
    const char* saved = std::getenv("OCIO");
    const std::string keep = saved ? saved : "";
    unsetenv("OCIO");
    e = error_of([] { OcioConfig::load(""); });
    EXPECT_TRUE(has(e, "--ocio-config") && has(e, "$OCIO")) << e;
    setenv("OCIO", dir.file("config.ocio").c_str(), 1);
    EXPECT_EQ(OcioConfig::load("")->path(), dir.file("config.ocio"));
    if (saved)
        setenv("OCIO", keep.c_str(), 1);
    else
        unsetenv("OCIO");
}

}  // namespace
}  // namespace pv
