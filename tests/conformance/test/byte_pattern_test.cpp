#include "byte_pattern.hpp"

#include <gtest/gtest.h>

namespace ldoem::conformance {
namespace {

TEST(BytePattern, ExactMatch_HasNoMismatch) {
  const Bytes payload{0x81, 0x02, 0x00, 0x00, 0x00, 0x01};
  EXPECT_FALSE(compare(BytePattern::exactly(payload), payload));
}

TEST(BytePattern, DifferentByte_IsReportedWithCaret) {
  const BytePattern expected = BytePattern::exactly(Bytes{0x81, 0x02, 0x00, 0x00, 0x00, 0x01});
  const Bytes received{0x81, 0x02, 0x00, 0x00, 0x00, 0x03};
  const auto mismatch = compare(expected, received);
  ASSERT_TRUE(mismatch);
  EXPECT_EQ(mismatch->differing_positions, std::vector<std::size_t>{5});
  EXPECT_EQ(render_diff(expected, received, *mismatch, ""),
            "expected: 81 02 00 00 00 01\n"
            "received: 81 02 00 00 00 03\n"
            "                         ^^\n");
}

TEST(BytePattern, Holes_AcceptAnyValueAndShowAsDots) {
  const BytePattern expected = BytePattern::exactly(Bytes{0x82, 0x05, 0x12, 0x34}).with_hole(2, 2);
  EXPECT_FALSE(compare(expected, Bytes{0x82, 0x05, 0xAB, 0xCD}));
  EXPECT_EQ(format_pattern(expected), "82 05 .. ..");
}

TEST(BytePattern, ShortReply_MarksMissingBytes) {
  const BytePattern expected = BytePattern::exactly(Bytes{0x84, 0x04, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00});
  const auto mismatch = compare(expected, Bytes{0x84, 0x04, 0x00, 0x00, 0x00, 0x03});
  ASSERT_TRUE(mismatch);
  EXPECT_TRUE(mismatch->length_differs);
  EXPECT_EQ(mismatch->differing_positions, (std::vector<std::size_t>{6, 7}));
}

TEST(BytePattern, AtLeast_AllowsSurplusButExactDoesNot) {
  const BytePattern exact = BytePattern::exactly(Bytes{0x81, 0x02});
  const Bytes longer{0x81, 0x02, 0x99};
  EXPECT_TRUE(compare(exact, longer));
  EXPECT_FALSE(compare(exact.with_length_rule(LengthRule::at_least), longer));
}

TEST(BytePattern, KeepOnly_HolesEverythingElse) {
  const BytePattern kept = BytePattern::exactly(Bytes{0x81, 0x02, 0x00, 0x00, 0x00, 0x01}).keep_only({0, 1, 5});
  EXPECT_EQ(format_pattern(kept), "81 02 .. .. .. 01");
  EXPECT_FALSE(compare(kept, Bytes{0x81, 0x02, 0x11, 0x22, 0x33, 0x01}));
}

TEST(BytePattern, LongDiff_ShowsOnlyRowsWithDifferences) {
  Bytes payload(64, 0x00);
  Bytes received = payload;
  received[40] = 0xFF;
  const auto mismatch = compare(BytePattern::exactly(payload), received);
  ASSERT_TRUE(mismatch);
  const std::string diff = render_diff(BytePattern::exactly(payload), received, *mismatch, "");
  EXPECT_NE(diff.find("@0020"), std::string::npos);
  EXPECT_EQ(diff.find("@0000"), std::string::npos);
}

TEST(ParseHex, AcceptsSpacesAndCase_RejectsOddDigits) {
  EXPECT_EQ(parse_hex("02 55 aB"), (Bytes{0x02, 0x55, 0xAB}));
  EXPECT_FALSE(parse_hex("0"));
  EXPECT_FALSE(parse_hex("zz"));
}

}  // namespace
}  // namespace ldoem::conformance
