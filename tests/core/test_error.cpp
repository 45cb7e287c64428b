#include "nav/core/error.hpp"
#include "nav/core/units.hpp"

#include <gtest/gtest.h>

namespace nav {

TEST(Error, DescribesFileLineFieldAndMessage) {
  const Error error{"expected 4 node indices", "liver.msh", 12, "$Elements"};
  EXPECT_EQ(error.describe(), "liver.msh:12: $Elements: expected 4 node indices");
}

TEST(Error, LeavesOutEmptyParts) {
  EXPECT_EQ((Error{.message = "arena exhausted"}).describe(), "arena exhausted");
  EXPECT_EQ((Error{.message = "cannot open", .file = "a.vtu"}).describe(), "a.vtu: cannot open");
}

TEST(Result, HoldsValueOrError) {
  Result<int> good = 3;
  Result<int> bad = Error{.message = "no", .file = "f", .line = 1};
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(good.value(), 3);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().line, 1);
}

TEST(LengthUnit, ParsesTheThreeUnitsAndRejectsOthers) {
  EXPECT_EQ(parse_length_unit("mm"), LengthUnit::millimetre);
  EXPECT_EQ(parse_length_unit("cm"), LengthUnit::centimetre);
  EXPECT_EQ(parse_length_unit("m"), LengthUnit::metre);
  EXPECT_FALSE(parse_length_unit("inch").has_value());
  EXPECT_DOUBLE_EQ(metres_per_unit(LengthUnit::millimetre), 0.001);
}

}  // namespace nav
