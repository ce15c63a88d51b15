// tests/render/test_settings.cpp: the one table of RenderSettings' fields (core/render/settings.h). It lists every
// field of the struct (counted independently of the table), each once; two settings that differ in any one field
// compare unequal, describe differently, and read back from the partial renders' text as themselves; the text of the
// defaults and of strings from before the sky guide and the light tree is unchanged (existing partial files read).
// Test kinds: unit
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/base/error.h"
#include "core/partial/partial.h"
#include "core/render/settings.h"
#include "support/field_count.h"

namespace pv {
namespace {

using test::field_count;

// `s` with the table's field `f` changed to another value (another word, or the number plus one).
template <class Field>
RenderSettings changed(RenderSettings s, const Field& f) {
    using T = std::decay_t<decltype(s.*f.member)>;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
        s.*f.member = T(s.*f.member + 1);
    } else {
        for (size_t i = 0; i < f.name_count; ++i)
            if (f.names[i].value != s.*f.member) {
                s.*f.member = f.names[i].value;
                break;
            }
    }
    return s;
}

TEST(SettingsTable, ListsEveryFieldOnce) {
    std::set<std::string> keys, flags;
    size_t fields = 0;
    for_each_setting([&](const auto& f) {
        ++fields;
        keys.insert(f.key);
        flags.insert(f.flag);
        EXPECT_EQ(std::string(f.flag).rfind("--", 0), 0u) << f.flag;
        EXPECT_NE(std::string(f.help), "") << f.key;
    });
    EXPECT_EQ(fields, field_count<RenderSettings>()) << "a field of RenderSettings is missing from for_each_setting";
    EXPECT_EQ(keys.size(), fields);
    EXPECT_EQ(flags.size(), fields);
}

TEST(SettingsTable, EveryFieldChangesEqualityDescribeAndRoundTrips) {
    // From the defaults and from settings with every field changed, so that an omitted value is met both ways.
    RenderSettings other;
    for_each_setting([&](const auto& f) { other = changed(other, f); });
    for (const RenderSettings& base : {RenderSettings{}, other}) {
        EXPECT_EQ(parse_settings(base.describe(), "t"), base);
        size_t fields = 0;
        for_each_setting([&](const auto& f) {
            ++fields;
            const RenderSettings s = changed(base, f);
            EXPECT_FALSE(s == base) << f.key;
            EXPECT_TRUE(s != base) << f.key;
            EXPECT_NE(s.describe(), base.describe()) << f.key;
            EXPECT_EQ(parse_settings(s.describe(), "t"), s) << s.describe();
            EXPECT_EQ(parse_settings(s.describe(), "t").describe(), s.describe());
        });
        EXPECT_EQ(fields, field_count<RenderSettings>());
    }
}

// The text is a file format (pathview:settings of partial renders): the same bytes as before the table.
TEST(SettingsTable, TextIsUnchanged) {
    EXPECT_EQ(RenderSettings{}.describe(), "nee=on mis=on rr=on max_depth=1024 seed=0 sampler=sobol sky_guide=auto");
    RenderSettings s;
    s.light_sampling = false;
    s.mis = false;
    s.russian_roulette = false;
    s.max_depth = 7;
    s.seed = 4294967295u;
    s.sampler = SamplerKind::Independent;
    s.sky_guide = SkyGuideMode::On;
    s.light_sampler = LightSamplerKind::Tree;
    EXPECT_EQ(s.describe(),
              "nee=off mis=off rr=off max_depth=7 seed=4294967295 sampler=independent sky_guide=on "
              "light_sampler=tree");
    // Strings from before the sky guide (and the light tree) mean both off.
    const RenderSettings old = parse_settings("nee=on mis=on rr=on max_depth=1024 seed=3 sampler=independent", "t");
    EXPECT_EQ(old.sky_guide, SkyGuideMode::Off);
    EXPECT_EQ(old.light_sampler, LightSamplerKind::Power);
    EXPECT_EQ(old.seed, 3u);
}

TEST(SettingsTable, TextOtherThanDescribeIsRefused) {
    const std::string good = "nee=on mis=on rr=on max_depth=1024 seed=0 sampler=sobol";
    const std::vector<std::string> bads = {good + " sky_guide=off",
                                           good + " light_sampler=power",
                                           good + " sky_guide=maybe",
                                           good + " seed=1",
                                           "nee=on mis=on rr=on max_depth=1024 seed=0 sampler=ind",
                                           "mis=on nee=on rr=on max_depth=1024 seed=0 "
                                           "sampler=sobol",
                                           "nee=on mis=on rr=on max_depth=01024 seed=0 sampler=sobol",
                                           "nee=on mis=on rr=on max_depth=1024 seed=4294967296 sampler=sobol",
                                           "nee=on mis=on rr=on max_depth=2147483648 seed=0 sampler=sobol",
                                           "nee=yes " + good.substr(7),
                                           good + " extra=1",
                                           good.substr(7),
                                           "",
                                           good + " "};
    for (const std::string& bad : bads) {
        EXPECT_THROW(parse_settings(bad, "t"), Error) << bad;
    }
    try {
        parse_settings(good + " x", "part.exr");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "part.exr: settings '" + good + " x' are not understood by " + partial_version());
    }
}

// README's "estimator" row of the options table is what the table says: each flag in order with its distinct words
// (the first word of each value) or N for a number. A flag added to the table and not to README fails here.
TEST(SettingsTable, ReadmeEstimatorRowIsTheTable) {
    std::string row = "| estimator |";
    bool first = true;
    for_each_setting([&](const auto& f) {
        row += first ? " `" : " ";
        first = false;
        row += f.flag;
        if (f.names == nullptr) {
            row += " N";
            return;
        }
        std::string words;
        for (size_t i = 0; i < f.name_count; ++i) {
            bool seen = false;
            for (size_t j = 0; j < i; ++j) seen = seen || f.names[j].value == f.names[i].value;
            if (!seen) words += (words.empty() ? " " : "\\|") + std::string(f.names[i].name);
        }
        row += words;
    });
    row += "` |";
    std::ifstream readme(std::string(PATHVIEW_SOURCE_DIR) + "/README.md");
    ASSERT_TRUE(readme) << PATHVIEW_SOURCE_DIR "/README.md";
    std::string line, found;
    while (std::getline(readme, line))
        if (line.rfind("| estimator |", 0) == 0) found = line;
    EXPECT_EQ(found, row);
}

}  // namespace
}  // namespace pv
