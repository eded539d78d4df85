#include "vector_table.hpp"

#include <gtest/gtest.h>

namespace ldoem::conformance {
namespace {

TEST(VectorTable, EmbeddedCopy_LoadsEveryRow) {
  auto table = load_vector_table(embedded_vectors_yaml());
  ASSERT_TRUE(table) << table.error();
  EXPECT_EQ(table->tcp_requests.size(), 41u);
  EXPECT_EQ(table->tcp_replies.size(), 22u);
  EXPECT_EQ(table->serial_requests.size(), 22u);
  const RequestVector* status = table->request("GET_STATUS");
  ASSERT_NE(status, nullptr);
  EXPECT_EQ(status->payload, (Bytes{0x01, 0x02}));
}

TEST(VectorTable, AssertedColumn_ResolvesIdemAndPlus) {
  auto table = load_vector_table(embedded_vectors_yaml());
  ASSERT_TRUE(table);
  const ReplyVector* measure = table->reply("GET_STATUS, MEASURE, motor OK");
  ASSERT_NE(measure, nullptr);
  EXPECT_EQ(measure->asserted.positions, (std::vector<std::size_t>{0, 1, 5}));
  const ReplyVector* ok = table->reply("TRANS_MEASURE OK");
  ASSERT_NE(ok, nullptr);
  EXPECT_EQ(ok->asserted.positions, (std::vector<std::size_t>{0, 1, 5, 6, 7}));
  EXPECT_EQ(format_pattern(ok->device_pattern()), "84 04 .. .. .. 03 00 00");
  const ReplyVector* signal = table->reply("GET_SIGNAL port 0x01");
  ASSERT_NE(signal, nullptr);
  EXPECT_EQ(format_pattern(signal->device_pattern()), "81 04 .. 01");
}

TEST(VectorTable, ProfileRow_LeavesSenstatBytes0To2Open) {
  auto table = load_vector_table(embedded_vectors_yaml());
  ASSERT_TRUE(table);
  const ReplyVector& profile = table->tcp_replies[20];
  const BytePattern pattern = profile.device_pattern();
  const std::size_t n = pattern.bytes.size();
  EXPECT_FALSE(pattern.bytes[n - 4]);
  EXPECT_FALSE(pattern.bytes[n - 2]);
  EXPECT_EQ(pattern.bytes[n - 1], std::optional<std::uint8_t>(0x03));
  EXPECT_EQ(pattern.bytes[n - 5], profile.payload[n - 5]);
}

TEST(VectorTable, BadFrame_IsRejectedWithItsRow) {
  auto table = load_vector_table("tcp_requests:\n  - {name: x, frame: \"02 55 53 50 00 00 00 02 01 02 04\"}\n");
  ASSERT_FALSE(table);
  EXPECT_NE(table.error().find("tcp_requests[0]"), std::string::npos);
}

TEST(ParseAsserted, UnknownText_IsAnError) { EXPECT_FALSE(parse_asserted("some bytes", {})); }

TEST(SerialVector, Telegram_IsStxAsciiEtx) {
  SerialVector vector{"GET_STATUS", "00100003000001026d36"};
  const Bytes telegram = vector.telegram();
  EXPECT_EQ(telegram.front(), 0x02);
  EXPECT_EQ(telegram.back(), 0x03);
  EXPECT_EQ(telegram.size(), 22u);
}

}  // namespace
}  // namespace ldoem::conformance
