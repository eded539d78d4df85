// ReplayModel: the recorded device as the daemon's device model. Telegrams leave per connection
// in order at their recorded times, one per event, later when the endpoint is busy (D10); a
// closed connection forgets them; a broken frame gets the D2 reply; profiles are counted.
#include <gtest/gtest.h>

#include <sstream>

#include "ldoem/replay/replay_model.hpp"
#include "recorded_telegrams.hpp"

namespace ldoem::replay {
namespace {

using capture::CapturedTelegram;
using protocol::ConnectionId;
using protocol::Transport;
using protocol::WireDirection;
using std::chrono::milliseconds;
using test::kGetStatus;
using test::kStatusIdle;
using test::profile;

const Bytes kGetProfileTwo{0x03, 0x01, 0x00, 0x02, 0x39, 0xFF};

struct RecordedTransportQuery final : control::TransportQuery {
  bool busy_now = false;
  bool busy(ConnectionId) const override { return busy_now; }
};

std::vector<Exchange> recording() {
  const auto at = [](int ms, WireDirection direction, Bytes payload) {
    return CapturedTelegram{milliseconds(ms), Transport::tcp, direction, 0, std::move(payload)};
  };
  return capture::exchanges_of({at(10, WireDirection::host_to_device, kGetStatus),
                                 at(12, WireDirection::device_to_host, kStatusIdle),
                                 at(100, WireDirection::host_to_device, kGetProfileTwo),
                                 at(180, WireDirection::device_to_host, profile(1)),
                                 at(260, WireDirection::device_to_host, profile(2))},
                                Transport::tcp);
}

struct Model {
  std::vector<std::string> warnings;
  std::ostringstream report;
  ReplayModel model{ReplayDevice(recording()), [this](const std::string& line) { warnings.push_back(line); },
                    report};
};

const ConnectionId kHost{Transport::tcp, 1};

TEST(ReplayModel, Answers_LeaveAtTheirRecordedTimes_OnePerEvent) {
  Model m;
  RecordedTransportQuery transport;
  control::Actions out = m.model.handle_request(milliseconds(1000), kHost, kGetStatus, transport);
  EXPECT_TRUE(out.telegrams.empty());
  ASSERT_EQ(out.timers.size(), 1u);
  EXPECT_EQ(out.timers[0].at, milliseconds(1002));
  out = m.model.on_timer(milliseconds(1002), out.timers[0].id, transport);
  ASSERT_EQ(out.telegrams.size(), 1u);
  EXPECT_EQ(out.telegrams[0].payload, kStatusIdle);
  EXPECT_EQ(out.telegrams[0].kind, control::TelegramKind::reply);
  EXPECT_TRUE(out.timers.empty());

  out = m.model.handle_request(milliseconds(2000), kHost, kGetProfileTwo, transport);
  ASSERT_EQ(out.timers.size(), 1u);
  // Both profiles are due: the first leaves, the second waits for the next event at once.
  out = m.model.on_timer(milliseconds(3000), out.timers[0].id, transport);
  ASSERT_EQ(out.telegrams.size(), 1u);
  EXPECT_EQ(out.telegrams[0].payload, profile(1));
  EXPECT_EQ(out.telegrams[0].kind, control::TelegramKind::profile);
  ASSERT_EQ(out.timers.size(), 1u);
  EXPECT_EQ(out.timers[0].at, milliseconds(3000));
  // The endpoint is still busy: look again a millisecond later.
  transport.busy_now = true;
  out = m.model.on_timer(milliseconds(3000), out.timers[0].id, transport);
  EXPECT_TRUE(out.telegrams.empty());
  ASSERT_EQ(out.timers.size(), 1u);
  EXPECT_EQ(out.timers[0].at, milliseconds(3001));
  transport.busy_now = false;
  out = m.model.on_timer(milliseconds(3001), out.timers[0].id, transport);
  ASSERT_EQ(out.telegrams.size(), 1u);
  EXPECT_EQ(out.telegrams[0].payload, profile(2));
  EXPECT_EQ(m.model.diagnostics().profiles_sent, 2u);
  m.model.report_at_exit();
  EXPECT_EQ(m.report.str(), "ldoem-emud: replay: requests=2 in_order=2 out_of_order=0 unexpected=0\n");
}

TEST(ReplayModel, AClosedConnection_ForgetsWhatWasDue) {
  Model m;
  RecordedTransportQuery transport;
  const control::Actions asked = m.model.handle_request(milliseconds(0), kHost, kGetProfileTwo, transport);
  ASSERT_EQ(asked.timers.size(), 1u);
  const control::Actions closed = m.model.on_connection_closed(milliseconds(10), kHost);
  EXPECT_EQ(closed.cancelled_timers, std::vector<control::TimerId>{asked.timers[0].id});
  EXPECT_TRUE(m.model.on_timer(milliseconds(80), asked.timers[0].id, transport).telegrams.empty());
}

TEST(ReplayModel, UnrecordedRequest_GetsTheFailureReplyAndAWarning) {
  Model m;
  RecordedTransportQuery transport;
  const control::Actions out = m.model.handle_request(milliseconds(5), kHost, Bytes{0x02, 0x04, 0x00, 0x07}, transport);
  ASSERT_EQ(out.telegrams.size(), 1u);
  EXPECT_EQ(out.telegrams[0].payload, (Bytes{0xFF, 0x00, 0x02, 0x04, 0x00, 0x03}));
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("is not in the recording"), std::string::npos);
}

TEST(ReplayModel, BrokenFrame_GetsTheD2Reply) {
  Model m;
  const control::Actions out =
      m.model.on_framing_error(milliseconds(5), kHost, protocol::FramingError{protocol::DecodeError::bad_checksum, 0x0102});
  ASSERT_EQ(out.telegrams.size(), 1u);
  EXPECT_EQ(out.telegrams[0].payload, (Bytes{0xFF, 0x00, 0x01, 0x02, 0x00, 0x05}));
}

}  // namespace
}  // namespace ldoem::replay
