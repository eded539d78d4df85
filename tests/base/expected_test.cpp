#include <gtest/gtest.h>

#include <string>

#include "ldoem/base/expected.hpp"

namespace ldoem::base {
namespace {

Expected<int, std::string> half(int value) {
  if (value % 2 != 0) return Unexpected(std::string("odd"));
  return value / 2;
}

TEST(Expected, Value_HoldsIt) {
  const auto result = half(8);
  ASSERT_TRUE(result);
  EXPECT_EQ(*result, 4);
  EXPECT_EQ(result.value_or(-1), 4);
}

TEST(Expected, Error_HoldsItAndFallsBack) {
  const auto result = half(7);
  ASSERT_FALSE(result.has_value());
  EXPECT_EQ(result.error(), "odd");
  EXPECT_EQ(result.value_or(-1), -1);
}

TEST(Expected, SameTypeForValueAndError_StaysApart) {
  const Expected<std::string, std::string> value = std::string("v");
  const Expected<std::string, std::string> error = Unexpected(std::string("e"));
  EXPECT_TRUE(value);
  EXPECT_EQ(*value, "v");
  EXPECT_FALSE(error);
  EXPECT_EQ(error.error(), "e");
}

}  // namespace
}  // namespace ldoem::base
