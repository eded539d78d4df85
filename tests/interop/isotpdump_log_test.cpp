// The isotpdump reader on lines captured from can-utils 2020.11 inside UML (with -c and -a);
// these run anywhere, so a change in the reader shows up without the vcan harness.
#include "isotpdump_log.hpp"

#include <gtest/gtest.h>

namespace ldoem::interop {
namespace {

using protocol::Bytes;
using protocol::IsoTpFrameType;

// Captured: cansend 6C0#020102, 6C1#100A8102000000, 6C0#300000, 6C1#2101020304,
// 6C1#1000000010000102 with `isotpdump -s 6C0 -d 6C1 -c -a vcan0`.
constexpr const char* kCaptured =
    "\x1b[31m vcan0  6C0  [3]  [SF] ln: 2    data: 01 02                 -  '..'\x1b[0m\n"
    "\x1b[34m vcan0  6C1  [7]  [FF] ln: 10   data: 81 02 00 00 00        -  '.....'\x1b[0m\n"
    "\x1b[31m vcan0  6C0  [3]  [FC] FC: 0 = CTS # BS: 0 = off # STmin: 0x00 = 0 ms\x1b[0m\n"
    "\x1b[34m vcan0  6C1  [5]  [CF] sn: 1    data: 01 02 03 04           -  '....'\x1b[0m\n"
    "\x1b[34m vcan0  6C1  [8]  [FF] ln: 4096 data: 01 02                 -  '..'\x1b[0m\n";

TEST(IsotpdumpLog, CapturedColourLines_ParseIntoTypedFrames) {
  const auto frames = parse_isotpdump(kCaptured);
  ASSERT_TRUE(frames) << frames.error();
  ASSERT_EQ(frames->size(), 5u);
  EXPECT_EQ((*frames)[0].id, 0x6C0u);
  EXPECT_EQ((*frames)[0].type, IsoTpFrameType::single_frame);
  EXPECT_EQ((*frames)[0].announced_length, std::optional<std::uint64_t>(2));
  EXPECT_EQ((*frames)[0].data, (Bytes{0x01, 0x02}));
  EXPECT_EQ((*frames)[1].dlc, 7);
  EXPECT_EQ((*frames)[1].data, (Bytes{0x81, 0x02, 0x00, 0x00, 0x00}));
  EXPECT_EQ((*frames)[2].type, IsoTpFrameType::flow_control);
  EXPECT_EQ((*frames)[2].flow_status, std::optional<std::uint8_t>(0));
  EXPECT_EQ((*frames)[2].block_size, std::optional<std::uint8_t>(0));
  EXPECT_EQ((*frames)[2].st_min_byte, std::optional<std::uint8_t>(0));
  EXPECT_EQ((*frames)[3].sequence, std::optional<std::uint8_t>(1));
  EXPECT_EQ((*frames)[4].announced_length, std::optional<std::uint64_t>(4096));  // 32-bit escape
}

TEST(IsotpdumpLog, PlainLinesWithoutAscii_ParseTheSame) {
  const auto frames = parse_isotpdump(" vcan0  6C1  [8]  [CF] sn: A    data: 11 22 33 44 55 66 77\n");
  ASSERT_TRUE(frames) << frames.error();
  ASSERT_EQ(frames->size(), 1u);
  EXPECT_EQ((*frames)[0].sequence, std::optional<std::uint8_t>(10));
  EXPECT_EQ((*frames)[0].data, (Bytes{0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77}));
}

TEST(IsotpdumpLog, LineThatIsNoFrame_IsAnErrorNamingTheLine) {
  const auto frames = parse_isotpdump(" vcan0  6C0  [3]  [SF] ln: 2    data: 01 02\nsocket: Address family not supported\n");
  ASSERT_FALSE(frames);
  EXPECT_NE(frames.error().find("line 2"), std::string::npos) << frames.error();
}

TEST(IsotpdumpLog, FirstFrameAndConsecutiveFrames_ReassembleAndCutPadding) {
  const auto frames = parse_isotpdump(
      " vcan0  6C1  [8]  [FF] ln: 14   data: 01 02 03 04 05 06\n"
      " vcan0  6C0  [3]  [FC] FC: 0 = CTS # BS: 0 = off # STmin: 0x00 = 0 ms\n"
      " vcan0  6C1  [8]  [CF] sn: 1    data: 07 08 09 0A 0B 0C 0D\n"
      " vcan0  6C1  [8]  [CF] sn: 2    data: 0E CC CC CC CC CC CC\n");
  ASSERT_TRUE(frames) << frames.error();
  const Reassembly result = reassemble(*frames);
  EXPECT_TRUE(result.problems.empty());
  EXPECT_TRUE(result.unfinished_ids.empty());
  ASSERT_EQ(result.messages.size(), 1u);
  EXPECT_EQ(result.messages[0].frames, 3u);
  EXPECT_EQ(result.messages[0].payload,
            (Bytes{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14}));
}

TEST(IsotpdumpLog, WrongSequenceNumber_IsAProblemAndDropsTheMessage) {
  const auto frames = parse_isotpdump(
      " vcan0  6C1  [8]  [FF] ln: 20   data: 01 02 03 04 05 06\n"
      " vcan0  6C1  [8]  [CF] sn: 2    data: 07 08 09 0A 0B 0C 0D\n");
  ASSERT_TRUE(frames) << frames.error();
  const Reassembly result = reassemble(*frames);
  EXPECT_TRUE(result.messages.empty());
  ASSERT_EQ(result.problems.size(), 1u);
  EXPECT_EQ(result.problems[0], "6C1: CF sn 2 where 1 was due");
}

TEST(IsotpdumpLog, MessageCutShort_IsReportedUnfinished) {
  const auto frames = parse_isotpdump(" vcan0  6C1  [8]  [FF] ln: 20   data: 01 02 03 04 05 06\n");
  ASSERT_TRUE(frames) << frames.error();
  const Reassembly result = reassemble(*frames);
  EXPECT_EQ(result.unfinished_ids, std::vector<std::uint32_t>{0x6C1});
}

}  // namespace
}  // namespace ldoem::interop
