// ReplayDevice: a recorded conversation answered again, in order and out of order, with the
// recorded delays (scaled), and the D2 failure reply for what was never recorded.
#include <gtest/gtest.h>

#include "ldoem/protocol/messages.hpp"
#include "ldoem/replay/replay_device.hpp"
#include "recorded_telegrams.hpp"

namespace ldoem::replay {
namespace {

using capture::CapturedTelegram;
using protocol::WireDirection;
using protocol::Transport;
using std::chrono::milliseconds;
using test::kGetStatus;
using test::kStatusIdle;
using test::profile;

const Bytes kGetProfileOne{0x03, 0x01, 0x00, 0x01, 0x39, 0xFF};

CapturedTelegram request(int ms, Bytes payload, protocol::Transport transport = protocol::Transport::tcp) {
  return {milliseconds(ms), transport, WireDirection::host_to_device, 0, std::move(payload)};
}
CapturedTelegram answer(int ms, Bytes payload, protocol::Transport transport = protocol::Transport::tcp) {
  return {milliseconds(ms), transport, WireDirection::device_to_host, 0, std::move(payload)};
}

std::vector<CapturedTelegram> scan_like_recording() {
  return {
      answer(0, kStatusIdle),  // before any request: dropped
      request(10, kGetStatus),         answer(12, kStatusIdle),
      request(100, kGetProfileOne),    answer(180, profile(1)),
      request(300, kGetProfileOne),    answer(390, profile(2)),
      request(500, Bytes{0x04, 0x02}), answer(501, Bytes{0x84, 0x02, 0, 0, 0, 1}),
      request(600, kGetStatus, protocol::Transport::can),
  };
}

TEST(Exchanges, AreCutAtEachRequestWithDelaysAfterIt) {
  const auto exchanges = capture::exchanges_of(scan_like_recording(), protocol::Transport::tcp);
  ASSERT_EQ(exchanges.size(), 4u);
  EXPECT_EQ(exchanges[0].request, kGetStatus);
  ASSERT_EQ(exchanges[1].answers.size(), 1u);
  EXPECT_EQ(exchanges[1].answers[0], (RecordedAnswer{milliseconds(80), profile(1)}));
  EXPECT_EQ(capture::exchanges_of(scan_like_recording(), protocol::Transport::can).size(), 1u);
  EXPECT_EQ(capture::busiest_transport(scan_like_recording()), protocol::Transport::tcp);
  EXPECT_EQ(capture::busiest_transport({}), std::nullopt);
}

TEST(ReplayDevice, IdenticalRequests_AreAnsweredInRecordedOrder) {
  ReplayDevice device(capture::exchanges_of(scan_like_recording(), protocol::Transport::tcp));
  EXPECT_EQ(device.on_request(milliseconds(1000), kGetStatus).telegrams,
            (std::vector<ScheduledTelegram>{{milliseconds(1002), kStatusIdle}}));
  // Two identical GET_PROFILE requests get the first, then the second recorded profile.
  EXPECT_EQ(device.on_request(milliseconds(2000), kGetProfileOne).telegrams,
            (std::vector<ScheduledTelegram>{{milliseconds(2080), profile(1)}}));
  EXPECT_EQ(device.on_request(milliseconds(3000), kGetProfileOne).telegrams,
            (std::vector<ScheduledTelegram>{{milliseconds(3090), profile(2)}}));
  EXPECT_EQ(device.counters().in_order, 3u);
  EXPECT_EQ(device.unused_exchanges(), 1u);
}

TEST(ReplayDevice, OutOfOrderAndRepeatedRequests_FindTheirExchange) {
  ReplayDevice device(capture::exchanges_of(scan_like_recording(), protocol::Transport::tcp));
  const auto idle = device.on_request(milliseconds(0), Bytes{0x04, 0x02});
  ASSERT_EQ(idle.exchange, 3u);
  EXPECT_EQ(idle.telegrams[0].payload, (Bytes{0x84, 0x02, 0, 0, 0, 1}));
  const auto status = device.on_request(milliseconds(5), kGetStatus);  // earlier in the recording
  EXPECT_EQ(status.exchange, 0u);
  EXPECT_FALSE(status.diagnostic.has_value());
  EXPECT_EQ(device.counters().out_of_order, 2u);  // both skipped the next exchange
}

TEST(ReplayDevice, Speed_ScalesTheRecordedDelays) {
  ReplayDevice device(capture::exchanges_of(scan_like_recording(), protocol::Transport::tcp), 4.0);
  (void)device.on_request(milliseconds(0), kGetStatus);
  EXPECT_EQ(device.on_request(milliseconds(0), kGetProfileOne).telegrams[0].at, milliseconds(20));
}

TEST(ReplayDevice, UnrecordedValidRequest_GetsReason3AndADiagnostic) {
  ReplayDevice device(capture::exchanges_of(scan_like_recording(), protocol::Transport::tcp));
  const Bytes get_signal{0x01, 0x04};
  const auto reply = device.on_request(milliseconds(7), get_signal);
  ASSERT_EQ(reply.telegrams.size(), 1u);
  EXPECT_EQ(reply.telegrams[0].at, milliseconds(7));
  EXPECT_EQ(reply.telegrams[0].payload, (Bytes{0xFF, 0x00, 0x01, 0x04, 0x00, 0x03}));
  ASSERT_TRUE(reply.diagnostic.has_value());
  EXPECT_NE(reply.diagnostic->find("GET_SIGNAL"), std::string::npos) << *reply.diagnostic;
  EXPECT_EQ(device.counters().unexpected, 1u);
}

TEST(ReplayDevice, InvalidRequest_GetsTheReasonDecodeRequestGives) {
  ReplayDevice device(capture::exchanges_of(scan_like_recording(), protocol::Transport::tcp));
  EXPECT_EQ(device.on_request(milliseconds(0), Bytes{0x05, 0x01}).telegrams[0].payload,
            (Bytes{0xFF, 0x00, 0x05, 0x01, 0x00, 0x01}));  // unknown service
  EXPECT_EQ(device.on_request(milliseconds(0), Bytes{0x01, 0x01}).telegrams[0].payload,
            (Bytes{0xFF, 0x00, 0x01, 0x01, 0x00, 0x02}));  // GET_IDENTIFICATION without its item
  EXPECT_EQ(device.on_request(milliseconds(0), Bytes{0x01}).telegrams[0].payload,
            (Bytes{0xFF, 0x00, 0x00, 0x00, 0x00, 0x02}));  // too short for a code
}

}  // namespace
}  // namespace ldoem::replay
