// Tests of the enum name tables (src/patlab/core/enum_names.h).
#include "patlab/core/enum_names.h"

#include <gtest/gtest.h>

#include "../expect_error.h"
#include "patlab/core/pattern.h"

namespace patlab {
namespace {

enum class Shade { kDark, kLight, kGrey };
constexpr EnumNames<Shade, 3> kShadeNames{{{
    {Shade::kDark, "dark"},
    {Shade::kLight, "light"},
    {Shade::kGrey, "grey"},
}}};
enum class Pair { kOne, kTwo };
constexpr EnumNames<Pair, 2> kPairNames{{{{Pair::kOne, "one"}, {Pair::kTwo, "two"}}}};

TEST(EnumNames, NameOfAndFindNameAreInverse) {
  for (const auto& [value, name] : kShadeNames.entries) {
    EXPECT_EQ(NameOf(value, kShadeNames), name);
    EXPECT_EQ(FindName(name, kShadeNames), value);
  }
  EXPECT_EQ(FindName("Dark", kShadeNames), std::nullopt);  // names are case-sensitive
  EXPECT_EQ(FindName("", kShadeNames), std::nullopt);
  static_assert(NameOf(Shade::kGrey, kShadeNames) == "grey");
}

TEST(EnumNames, NameListReadsAsAnEnglishList) {
  EXPECT_EQ(NameList(kShadeNames), "\"dark\", \"light\" or \"grey\"");
  EXPECT_EQ(NameList(kPairNames), "\"one\" or \"two\"");
}

TEST(EnumNames, ParseNameThrowsNamingWhatAndTheChoices) {
  EXPECT_EQ(ParseName("light", kShadeNames, "shade"), Shade::kLight);
  EXPECT_INPUT_ERROR(ParseName("pink", kShadeNames, "shade"),
                     "shade is \"pink\"; expected \"dark\", \"light\" or \"grey\"");
  EXPECT_INPUT_ERROR(ParseName("role", kPatchRoleNames, "role in [[patch]] 2"),
                     "role in [[patch]] 2 is \"role\"; expected \"key\", \"id\" or \"fixed\"");
}

}  // namespace
}  // namespace patlab
