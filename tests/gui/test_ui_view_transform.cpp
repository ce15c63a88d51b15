// tests/gui/test_ui_view_transform.cpp: the viewer's choice of view transform (ui/display_transform.h), window-free:
// T cycles the built-ins and OpenColorIO only with a config, a bad display or view keeps the view on screen and says
// why, and a PNG snapshot goes through the transform and exposure on screen.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "display_transform.h"
#include "tests/image/ocio_test_config.h"

namespace pv::ui {
namespace {

TEST(UiViewTransform, CycleSkipsOpenColorIoWithoutAConfig) {
    DisplayParams d;
    d.transform = ViewTransform::Clamp;
    OcioChoice none;
    std::vector<ViewTransform> seen;
    for (int i = 0; i < 6; ++i) {
        cycle_view_transform(d, none);
        seen.push_back(d.transform);
    }
    EXPECT_EQ(seen,
              (std::vector<ViewTransform>{ViewTransform::Reinhard, ViewTransform::Aces, ViewTransform::Agx,
                                          ViewTransform::PbrNeutral, ViewTransform::Clamp, ViewTransform::Reinhard}));
    EXPECT_FALSE(d.ocio);
}

TEST(UiViewTransform, OpenColorIoChoiceKeepsTheViewOnFailure) {
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("pv_ui_ocio_" + std::to_string(getpid()) + ".ocio");
    std::ofstream(file) << test::kOcioTestConfig;
    OcioChoice choice;
    choice.config = OcioConfig::load(file.string());
    DisplayParams d;
    d.transform = ViewTransform::PbrNeutral;
    cycle_view_transform(d, choice);  // pbr-neutral -> ocio: the config's default display and view
    ASSERT_EQ(d.transform, ViewTransform::Ocio);
    ASSERT_TRUE(d.ocio);
    EXPECT_EQ(d.ocio->describe(), "sRGB/Standard");
    EXPECT_TRUE(choose_ocio_view(d, choice, "sRGB", "Gamma 2.2"));
    const auto gamma = d.ocio;
    EXPECT_FALSE(choose_ocio_view(d, choice, "sRGB", "Filmic"));
    EXPECT_EQ(d.ocio, gamma);  // unchanged
    EXPECT_NE(choice.status.find("no view 'Filmic'"), std::string::npos) << choice.status;
    EXPECT_TRUE(choose_ocio_view(d, choice, "Raw", ""));
    EXPECT_TRUE(choice.status.empty());
    d.exposure = 1.5f;
    const DisplayTransform t = display_transform(d);
    EXPECT_EQ(t.transform, ViewTransform::Ocio);
    EXPECT_EQ(t.exposure, 1.5f);
    EXPECT_EQ(t.describe(), "ocio Raw/Linear, exposure +1.5");
    cycle_view_transform(d, choice);  // ocio -> clamp
    EXPECT_EQ(d.transform, ViewTransform::Clamp);
    std::filesystem::remove(file);
}

}  // namespace
}  // namespace pv::ui
