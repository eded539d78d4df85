// libldoem on the unhappy paths of D11 (docs/faults.md, "Host side"): every error kind's
// classification, device faults read from status bytes, corrupted replies, bounded reconnects,
// and the TCP transport's resynchronisation after a frame cut short on the wire.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "fake_transport.hpp"
#include "ldoem/driver/error.hpp"
#include "ldoem/driver/scanner.hpp"
#include "ldoem/driver/tcp_transport.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/tcp_framing.hpp"
#include "tcp_server.hpp"
#include "test_support.hpp"

namespace ldoem::driver {
namespace {

namespace p = protocol;
using test::encoded;
using test::FakeTransport;
using test::kStatusIdle;
using namespace std::chrono_literals;

// ------------------------------------------------------------------------ classification

struct KindRow {
  ErrorKind kind;
  Recovery recovery;
};

TEST(FaultClassification, EveryKindHasItsRecovery) {
  const KindRow rows[] = {
      {ErrorKind::timeout, Recovery::retry},           // drop_reply, delay_reply, a stall of the wire
      {ErrorKind::busy, Recovery::retry},
      {ErrorKind::interrupted, Recovery::retry},
      {ErrorKind::framing, Recovery::retry},           // a broken ISO-TP message, a bad flow control
      {ErrorKind::corrupted_reply, Recovery::retry},   // truncate_reply
      {ErrorKind::connection_closed, Recovery::reconnect},  // tcp_reset, power_cycle
      {ErrorKind::service_failure, Recovery::none},
      {ErrorKind::device_fault, Recovery::reset_device},    // motor_stall, motor_overspeed, encoder_error
      {ErrorKind::unexpected_reply, Recovery::none},
      {ErrorKind::refused, Recovery::none},
      {ErrorKind::system, Recovery::none},
      {ErrorKind::unsupported, Recovery::none},
      {ErrorKind::invalid_argument, Recovery::none},
      {ErrorKind::wrong_state, Recovery::none},
  };
  EXPECT_EQ(std::size(rows), static_cast<std::size_t>(ErrorKind::wrong_state) + 1) << "a kind without a row";
  for (const KindRow& row : rows) {
    const DriverError error = make_error(row.kind, "op", "obj");
    EXPECT_EQ(recovery_for(error), row.recovery) << describe(row.kind);
    const bool retryable = row.recovery == Recovery::retry || row.recovery == Recovery::reconnect;
    EXPECT_EQ(is_retryable(error), retryable) << describe(row.kind);
    EXPECT_EQ(is_retryable(row.kind), retryable) << describe(row.kind);
  }
}

TEST(FaultClassification, ServiceFailureReasonFive_IsRetryable_OthersFinal) {
  DriverError error = make_error(ErrorKind::service_failure, "GET_STATUS", "obj");
  error.failure_reason = p::FailureReason::framing;  // our request arrived corrupted (D2)
  EXPECT_EQ(recovery_for(error), Recovery::retry);
  EXPECT_TRUE(is_retryable(error));
  for (auto reason : {p::FailureReason::unknown_service, p::FailureReason::wrong_length, p::FailureReason::wrong_state,
                      p::FailureReason::out_of_range}) {
    error.failure_reason = reason;
    EXPECT_EQ(recovery_for(error), Recovery::none) << static_cast<int>(reason);
    EXPECT_FALSE(is_retryable(error));
  }
}

TEST(FaultClassification, RecoveryWords) {
  EXPECT_EQ(describe(Recovery::retry), "retryable");
  EXPECT_EQ(describe(Recovery::reconnect), "retryable after a reconnect");
  EXPECT_EQ(describe(Recovery::reset_device), "final until the device is reset");
  EXPECT_EQ(describe(Recovery::none), "final");
}

TEST(DeviceFaultIn, HealthyStatusesAreNoFault) {
  for (std::uint8_t byte : {0x01, 0x02, 0x03}) {
    EXPECT_FALSE(device_fault_in(p::StatusBlock{{}, p::StatusByte::from_byte(byte)}, "op", "obj")) << int(byte);
  }
}

TEST(DeviceFaultIn, MotorNibbleOrErrorMode_IsDeviceFaultWithTheByte) {
  struct Row {
    std::uint8_t byte;
    const char* words;
  };
  for (const Row& row : {Row{0xB3, "motor nibble 0x0B: motor fault)"}, Row{0xB4, "motor fault, sensor mode ERROR"},
                         Row{0x93, "spin too high"}, Row{0x43, "spin too low"}, Row{0x04, "sensor mode ERROR"}}) {
    const auto fault = device_fault_in(p::StatusBlock{{}, p::StatusByte::from_byte(row.byte)}, "TRANS_ROTATE", "tcp:x");
    ASSERT_TRUE(fault) << int(row.byte);
    EXPECT_EQ(fault->kind, ErrorKind::device_fault);
    EXPECT_EQ(fault->device_status, row.byte);
    EXPECT_FALSE(is_retryable(*fault));
    EXPECT_NE(describe(*fault).find(row.words), std::string::npos) << describe(*fault);
  }
  const auto stall = device_fault_in(p::StatusBlock{{}, p::StatusByte::from_byte(0xB4)}, "TRANS_ROTATE", "tcp:x");
  EXPECT_EQ(describe(*stall),
            "TRANS_ROTATE tcp:x: device fault: status 0xB4 (motor nibble 0x0B: motor fault, sensor mode ERROR)");
}

// ---------------------------------------------------------------------------- Scanner

class ScannerFaultTest : public ::testing::Test {
 protected:
  std::unique_ptr<FakeTransport> make_transport(FakeTransport::Log& log) {
    return std::make_unique<FakeTransport>(log, [this](const Bytes& request) {
      auto found = script_.find(request);
      return found == script_.end() ? std::vector<FakeTransport::Incoming>{} : found->second;
    });
  }
  void build(ScannerOptions options = {}) {
    scanner_ = std::make_unique<Scanner>(make_transport(log_), std::move(options));
    script_[encoded(p::GetStatus{})] = {kStatusIdle};
    ASSERT_TRUE(scanner_->connect());
  }
  std::map<Bytes, std::vector<FakeTransport::Incoming>> script_;
  // Both logs outlive scanner_ (members go in reverse order): its destructor closes the transport,
  // which writes to its log.
  FakeTransport::Log log_;
  FakeTransport::Log reopened_log_;  // of the transport a reconnect opens
  std::unique_ptr<Scanner> scanner_;
};

TEST_F(ScannerFaultTest, TransRotateWithMotorFaultStatus_IsDeviceFault) {
  build();
  // D11: while a motor fault lasts, TRANS_ROTATE fails at once with 84 03 00 00 00 B4.
  script_[encoded(p::TransRotate{0})] = {Bytes{0x84, 0x03, 0x00, 0x00, 0x00, 0xB4}};
  auto rotated = scanner_->trans_rotate();
  ASSERT_FALSE(rotated);
  EXPECT_EQ(rotated.error().kind, ErrorKind::device_fault);
  EXPECT_EQ(rotated.error().device_status, 0xB4);
  EXPECT_EQ(rotated.error().request_code, 0x0403);
  EXPECT_EQ(recovery_for(rotated.error()), Recovery::reset_device);
  EXPECT_NE(describe(rotated.error()).find("TRANS_ROTATE fake:scripted: device fault: status 0xB4"), std::string::npos);
}

TEST_F(ScannerFaultTest, TransMeasureWithOverspeed_IsDeviceFault) {
  build();
  script_[encoded(p::TransMeasure{})] = {
      encoded(p::Response{p::TransMeasureReply{p::make_status_block(p::SensorMode::measure, p::MotorMode::spin_too_high),
                                               p::measure_return::kOk}})};
  auto measured = scanner_->trans_measure();
  ASSERT_FALSE(measured);
  EXPECT_EQ(measured.error().kind, ErrorKind::device_fault);
  EXPECT_EQ(measured.error().device_status, 0x93);
}

TEST_F(ScannerFaultTest, TruncatedReply_IsRetryableCorruptedReply_AndTheRetrySucceeds) {
  build();
  const Bytes status_reply = kStatusIdle;
  script_[encoded(p::GetStatus{})] = {Bytes(status_reply.begin(), status_reply.begin() + 3)};  // truncate_reply
  auto first = scanner_->get_status();
  ASSERT_FALSE(first);
  EXPECT_EQ(first.error().kind, ErrorKind::corrupted_reply);
  EXPECT_TRUE(is_retryable(first.error()));
  script_[encoded(p::GetStatus{})] = {status_reply};
  EXPECT_TRUE(scanner_->get_status());
}

TEST_F(ScannerFaultTest, TruncatedProfile_IsCorruptedReply_AndTheStreamGoesOn) {
  build();
  p::Profile profile;
  profile.format = p::kFormatRange;
  p::SectorBlock sector;
  sector.points = {p::ProfilePoint{256, 0, 0}, p::ProfilePoint{512, 8, 0}};
  profile.sectors = {sector};
  const Bytes whole = p::encode_profile(profile);
  script_[encoded(p::GetProfile{0, p::kFormatRange})] = {Bytes(whole.begin(), whole.begin() + 6), whole};
  ASSERT_TRUE(scanner_->get_profile(0, p::kFormatRange));
  auto cut = scanner_->next_profile(Clock::now() + 1s);
  ASSERT_FALSE(cut);
  EXPECT_EQ(cut.error().kind, ErrorKind::corrupted_reply);
  EXPECT_EQ(scanner_->state(), LifecycleState::active);
  auto next = scanner_->next_profile(Clock::now() + 1s);
  ASSERT_TRUE(next) << describe(next.error());
  ASSERT_EQ(next->sectors.size(), 1u);
  EXPECT_EQ(next->sectors[0].points.size(), 2u);
  EXPECT_EQ(next->sectors[0].points[1].distance_q8_m, 512);
}

TEST_F(ScannerFaultTest, Reconnect_TriesABoundedNumberOfTimesThenSucceeds) {
  int opened = 0;
  std::vector<std::chrono::milliseconds> pauses;
  ScannerOptions options;
  options.reconnect = ReconnectPolicy{5, 250ms};
  options.sleep = [&pauses](std::chrono::milliseconds pause) { pauses.push_back(pause); };
  options.reopen = [&]() -> Expected<std::unique_ptr<TelegramTransport>, DriverError> {
    ++opened;
    if (opened < 3) {  // the device is still off: the peer closes at once
      return fail(make_error(ErrorKind::connection_closed, "connect", "fake"));
    }
    return std::unique_ptr<TelegramTransport>(make_transport(reopened_log_));
  };
  build(options);
  auto lost = scanner_->get_signal();  // nothing scripted: times out; pretend the peer reset
  scanner_->close();
  ASSERT_EQ(scanner_->state(), LifecycleState::closed);
  auto status = scanner_->reconnect();
  ASSERT_TRUE(status) << describe(status.error());
  EXPECT_EQ(opened, 3);
  EXPECT_EQ(pauses, (std::vector<std::chrono::milliseconds>{250ms, 250ms}));
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
  EXPECT_EQ(scanner_->counters().reconnects, 1u);
  EXPECT_EQ(reopened_log_.sent.size(), 1u);  // GET_STATUS on the new transport
}

TEST_F(ScannerFaultTest, Reconnect_GivesUpAfterItsAttempts) {
  int opened = 0;
  ScannerOptions options;
  options.reconnect = ReconnectPolicy{4, 1ms};
  options.sleep = [](std::chrono::milliseconds) {};
  options.reopen = [&]() -> Expected<std::unique_ptr<TelegramTransport>, DriverError> {
    ++opened;
    return fail(make_error(ErrorKind::system, "connect", "fake", "connection refused"));
  };
  build(options);
  auto status = scanner_->reconnect();
  ASSERT_FALSE(status);
  EXPECT_EQ(opened, 4);
  EXPECT_EQ(status.error().kind, ErrorKind::system);
  EXPECT_NE(status.error().detail.find("reconnect gave up after 4 attempts"), std::string::npos);
  EXPECT_EQ(scanner_->state(), LifecycleState::closed);
}

TEST_F(ScannerFaultTest, Reconnect_BacksOffUpToItsLongestPause) {
  int opened = 0;
  std::vector<std::chrono::milliseconds> pauses;
  ScannerOptions options;
  options.reconnect = ReconnectPolicy{6, 100ms, 2.0, 300ms};
  options.sleep = [&pauses](std::chrono::milliseconds pause) { pauses.push_back(pause); };
  options.reopen = [&]() -> Expected<std::unique_ptr<TelegramTransport>, DriverError> {
    ++opened;
    return fail(make_error(ErrorKind::connection_closed, "connect", "fake"));
  };
  build(options);
  ASSERT_FALSE(scanner_->reconnect());
  EXPECT_EQ(opened, 6);
  EXPECT_EQ(pauses, (std::vector<std::chrono::milliseconds>{100ms, 200ms, 300ms, 300ms, 300ms}));
  // The default is unchanged: 10 attempts, 500 ms apart, no backoff.
  const ReconnectPolicy defaults;
  EXPECT_EQ(defaults.attempts, 10u);
  for (std::uint32_t attempt = 2; attempt <= 10; ++attempt) EXPECT_EQ(reconnect_pause(defaults, attempt), 500ms);
  EXPECT_EQ(reconnect_pause(ReconnectPolicy{4000000000u, 10ms, 1.5, 1000ms}, 3999999999u), 1000ms);  // bounded work
}

TEST_F(ScannerFaultTest, Reconnect_WithoutAReopener_IsUnsupported) {
  build();
  auto status = scanner_->reconnect();
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().kind, ErrorKind::unsupported);
}

// ------------------------------------------------------------------ TCP resynchronisation

TEST(TcpResyncTransport, FrameCutShortOnTheWire_IsGivenUpAfterTheGap_AndTheNextReplyArrives) {
  const Bytes request = p::encode_tcp_frame(encoded(p::GetStatus{}));
  // First reply: a header promising 40 bytes, 3 sent (the rest lost); second: a whole reply.
  const Bytes cut = {0x02, 0x55, 0x53, 0x50, 0x00, 0x00, 0x00, 0x28, 0x81, 0x02, 0x00};
  test::ScriptedTcpServer server(
      {test::ServerStep{request.size(), cut}, test::ServerStep{request.size(), p::encode_tcp_frame(kStatusIdle)}});
  auto transport = TcpTransport::connect(TcpEndpoint{"127.0.0.1", server.port()});
  ASSERT_TRUE(transport) << describe(transport.error());
  ASSERT_TRUE((*transport)->send(encoded(p::GetStatus{}), Clock::now() + 1s));
  auto first = (*transport)->receive(Clock::now() + 100ms);
  ASSERT_FALSE(first);
  EXPECT_EQ(first.error().kind, ErrorKind::timeout);  // the cut frame never completes
  ASSERT_TRUE((*transport)->send(encoded(p::GetStatus{}), Clock::now() + 1s));
  const auto asked = Clock::now();
  auto second = (*transport)->receive(asked + 5s);
  ASSERT_TRUE(second) << describe(second.error());
  EXPECT_EQ(*second, kStatusIdle);
  EXPECT_LT(Clock::now() - asked, kTcpFrameGap + 2s);
  EXPECT_EQ((*transport)->counters().dropped_frames, 1u);
}

}  // namespace
}  // namespace ldoem::driver

namespace ldoem::driver {
namespace {

TEST(StaleReplies, ADuplicatedReplyIsNotTakenForTheNextRequestsAnswer) {
  const Bytes request = p::encode_tcp_frame(encoded(p::GetSyncClock{}));
  const Bytes first = p::encode_tcp_frame(Bytes{0x82, 0x05, 0x11, 0x11});
  const Bytes second = p::encode_tcp_frame(Bytes{0x82, 0x05, 0x22, 0x22});
  Bytes duplicated = first;  // D11 duplicate_reply: the same reply twice
  duplicated.insert(duplicated.end(), first.begin(), first.end());
  test::ScriptedTcpServer server({test::ServerStep{p::encode_tcp_frame(encoded(p::GetStatus{})).size(),
                                                   p::encode_tcp_frame(kStatusIdle)},
                                  test::ServerStep{request.size(), duplicated}, test::ServerStep{request.size(), second}});
  auto transport = TcpTransport::connect(TcpEndpoint{"127.0.0.1", server.port()});
  ASSERT_TRUE(transport) << describe(transport.error());
  Scanner scanner(std::move(*transport));
  ASSERT_TRUE(scanner.connect());
  auto one = scanner.get_sync_clock();
  ASSERT_TRUE(one) << describe(one.error());
  EXPECT_EQ(*one, 0x1111);
  auto two = scanner.get_sync_clock();
  ASSERT_TRUE(two) << describe(two.error());
  EXPECT_EQ(*two, 0x2222) << "the duplicate of the first reply was taken for the second";
  EXPECT_EQ(scanner.counters().stale_replies, 1u);
}

}  // namespace
}  // namespace ldoem::driver
