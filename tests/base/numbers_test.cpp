#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "ldoem/base/numbers.hpp"

namespace ldoem::base {
namespace {

TEST(ParseInteger, WholeTextInRange_IsTheValue) {
  EXPECT_EQ(parse_integer<std::uint16_t>("49152"), 49152);
  EXPECT_EQ(parse_integer<std::int64_t>("-240"), -240);
  EXPECT_EQ(parse_integer<std::uint32_t>("7FF", 16), 0x7FFU);
  EXPECT_EQ(parse_integer<std::uint32_t>("7ff", 16), 0x7FFU);
}

TEST(ParseInteger, AnythingElse_IsNoValue) {
  for (const char* text : {"", " 1", "1 ", "+1", "1x", "0x10", "1.0", "-"}) {
    EXPECT_FALSE(parse_integer<std::int32_t>(text)) << '"' << text << '"';
  }
  EXPECT_FALSE(parse_integer<std::uint16_t>("65536"));  // out of range
  EXPECT_FALSE(parse_integer<std::uint8_t>("-1"));
  EXPECT_FALSE(parse_integer<std::uint8_t>("G", 16));
}

TEST(ParseDouble, WholeTextFinite_IsTheValue) {
  EXPECT_EQ(parse_double("0.25"), 0.25);
  EXPECT_EQ(parse_double("-3"), -3.0);
  EXPECT_EQ(parse_double("1e-3"), 1e-3);
}

TEST(ParseDouble, AnythingElse_IsNoValue) {
  for (const char* text : {"", "1.0 ", " 1", "+1", "1,5", "abc", "1e999"}) {
    EXPECT_FALSE(parse_double(text)) << '"' << text << '"';
  }
}

TEST(ParseDouble, NonFinite_OnlyWhenAccepted) {
  EXPECT_FALSE(parse_double("nan"));
  EXPECT_FALSE(parse_double("-inf"));
  const auto nan = parse_double("nan", NonFinite::accept);
  ASSERT_TRUE(nan);
  EXPECT_TRUE(std::isnan(*nan));
  EXPECT_EQ(parse_double("-inf", NonFinite::accept), -INFINITY);
  EXPECT_FALSE(parse_double("nanx", NonFinite::accept));
}

}  // namespace
}  // namespace ldoem::base
