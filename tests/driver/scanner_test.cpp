// Scanner over a scripted transport: request bytes from spec 7.1, replies from spec 7.2 (or
// protocol's encoder where the spec has no row), D2 failures, timeouts, reply matching and the
// lifecycle.
#include "ldoem/driver/scanner.hpp"

#include <gtest/gtest.h>

#include <map>
#include <memory>

#include "fake_transport.hpp"
#include "test_support.hpp"

namespace ldoem::driver {
namespace {

namespace p = protocol;
using test::encoded;
using test::FakeTransport;
using test::hex_text;
using test::kStatusIdle;
using test::SpecVectors;
using test::tcp_payload;
using namespace std::chrono_literals;

Bytes request_payload(const std::string& name) { return tcp_payload(SpecVectors::get().request(name)); }
Bytes reply_payload(const std::string& name) { return tcp_payload(SpecVectors::get().reply(name)); }

Bytes failure(std::uint16_t request_code, p::FailureReason reason) {
  return encoded(p::Response{p::ServiceFailure{request_code, reason}});
}

const Bytes kProfileRange = reply_payload(
    "Profile 0x39FF: sent 1, count 100, layer 0, sector 0, step 0.5°, 3 points, t 0x1234→0x1236 ms, 0°→1°, "
    "distances 1 m / 2.5 m / 0");
const Bytes kCancelReply = reply_payload("CANCEL_PROFILE, MEASURE");

class ScannerTest : public ::testing::Test {
 protected:
  using Script = std::map<Bytes, std::vector<FakeTransport::Incoming>>;

  ScannerTest() { rebuild(); }

  // A fresh Scanner whose transport answers each request from `script_` (looked up by the
  // request payload at send time, so tests may add rows later).
  void rebuild(ScannerOptions options = {}) {
    auto transport = std::make_unique<FakeTransport>(log_, [this](const Bytes& request) {
      auto found = script_.find(request);
      return found == script_.end() ? std::vector<FakeTransport::Incoming>{} : found->second;
    });
    fake_ = transport.get();
    options.clock = [this] { return t0_; };
    scanner_ = std::make_unique<Scanner>(std::move(transport), options);
  }

  void on(const Bytes& request, std::vector<FakeTransport::Incoming> replies) { script_[request] = std::move(replies); }

  void connect() {
    on(request_payload("GET_STATUS"), {kStatusIdle});
    ASSERT_TRUE(scanner_->connect());
    log_.sent.clear();
    log_.send_deadlines.clear();
    log_.receive_deadlines.clear();
  }

  void start_stream(std::uint16_t count = 0) {
    ASSERT_TRUE(scanner_->get_profile(count, p::kFormatRange));
    ASSERT_EQ(scanner_->state(), LifecycleState::active);
  }

  const Bytes& last_sent() const { return log_.sent.back(); }

  FakeTransport::Log log_;
  FakeTransport* fake_ = nullptr;
  Script script_;
  Deadline t0_ = Deadline(std::chrono::hours(7));
  std::unique_ptr<Scanner> scanner_;
};

// ------------------------------------------------------------------ lifecycle and state

TEST_F(ScannerTest, Connect_SendsGetStatusAndMovesToConnected) {
  on(request_payload("GET_STATUS"), {kStatusIdle});
  EXPECT_EQ(scanner_->state(), LifecycleState::unconfigured);
  auto status = scanner_->connect();
  ASSERT_TRUE(status) << describe(status.error());
  EXPECT_EQ(status->status.status.sensor, p::SensorMode::idle);
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
  ASSERT_EQ(log_.sent.size(), 1u);
  EXPECT_EQ(last_sent(), request_payload("GET_STATUS"));
}

TEST_F(ScannerTest, ServiceWhileUnconfigured_IsWrongStateAndSendsNothing) {
  auto signal = scanner_->get_signal();
  ASSERT_FALSE(signal);
  EXPECT_EQ(signal.error().kind, ErrorKind::wrong_state);
  EXPECT_TRUE(log_.sent.empty());
}

TEST_F(ScannerTest, ServiceAfterClose_IsWrongStateAndTransportIsClosed) {
  connect();
  scanner_->close();
  EXPECT_TRUE(log_.closed);
  EXPECT_EQ(scanner_->state(), LifecycleState::closed);
  auto status = scanner_->get_status();
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().kind, ErrorKind::wrong_state);
  EXPECT_FALSE(scanner_->connect());
}

class ScannerLifecycleTest : public ScannerTest {
 protected:
  // Brings the fresh Scanner into `state` through the public API.
  void bring_to(LifecycleState state) {
    on(request_payload("GET_STATUS"), {kStatusIdle});
    on(encoded(p::Request{p::CancelProfile{}}), {kCancelReply});
    switch (state) {
      case LifecycleState::unconfigured:
        break;
      case LifecycleState::connected:
        ASSERT_TRUE(scanner_->set_state(LifecycleState::connected));
        break;
      case LifecycleState::active:
        ASSERT_TRUE(scanner_->set_state(LifecycleState::connected));
        ASSERT_TRUE(scanner_->set_state(LifecycleState::active));
        break;
      case LifecycleState::closed:
        scanner_->close();
        break;
    }
    ASSERT_EQ(scanner_->state(), state);
  }
};

TEST_F(ScannerLifecycleTest, EveryPair_EndsInTargetOrRefusesAndStays) {
  const LifecycleState states[] = {LifecycleState::unconfigured, LifecycleState::connected,
                                   LifecycleState::active, LifecycleState::closed};
  for (LifecycleState from : states) {
    for (LifecycleState to : states) {
      rebuild();
      bring_to(from);
      const auto result = scanner_->set_state(to);
      const bool refused = plan_transition(from, to) == LifecycleAction::refuse;
      EXPECT_EQ(result.has_value(), !refused) << describe(from) << " -> " << describe(to);
      EXPECT_EQ(scanner_->state(), refused ? from : to) << describe(from) << " -> " << describe(to);
      if (refused) {
        EXPECT_EQ(result.error().kind, ErrorKind::wrong_state);
      }
    }
  }
}

TEST_F(ScannerLifecycleTest, ActiveToConnected_SendsCancelProfile) {
  bring_to(LifecycleState::active);
  ASSERT_TRUE(scanner_->set_state(LifecycleState::connected));
  EXPECT_EQ(last_sent(), request_payload("CANCEL_PROFILE"));
}

TEST_F(ScannerLifecycleTest, ConnectedToActive_StreamsTheConfiguredFormat) {
  bring_to(LifecycleState::connected);
  ASSERT_TRUE(scanner_->set_state(LifecycleState::active));
  EXPECT_EQ(last_sent(), request_payload("GET_PROFILE stream 0x39FF"));
}

// ---------------------------------------------------------- every method: bytes and replies

TEST_F(ScannerTest, IdentifyAll_AsksElevenItemsInS1Order) {
  connect();
  const char* names[] = {"0x00", "0x01", "0x02", "0x03", "0x04", "0x10", "0x11", "0x12", "0x20", "0x21", "0x22"};
  for (std::size_t i = 0; i < std::size(names); ++i) {
    const std::string text = "item " + std::to_string(i);
    Bytes reply{0x81, 0x01};
    reply.insert(reply.end(), text.begin(), text.end());
    on(request_payload(std::string("GET_IDENTIFICATION ") + names[i]), {reply});
  }
  auto entries = scanner_->identify_all();
  ASSERT_TRUE(entries) << describe(entries.error());
  ASSERT_EQ(entries->size(), 11u);
  for (std::size_t i = 0; i < std::size(names); ++i) {
    EXPECT_EQ(log_.sent[i], request_payload(std::string("GET_IDENTIFICATION ") + names[i]));
    EXPECT_EQ((*entries)[i].item, kIdentificationItems[i]);
    EXPECT_EQ((*entries)[i].text, "item " + std::to_string(i));
  }
}

TEST_F(ScannerTest, GetIdentification_ReturnsTheText) {
  connect();
  on(request_payload("GET_IDENTIFICATION 0x01"), {reply_payload("GET_IDENTIFICATION, text 'LD-OEM' (text illustrative)")});
  auto text = scanner_->get_identification(0x01);
  ASSERT_TRUE(text);
  EXPECT_EQ(*text, "LD-OEM");
}

TEST_F(ScannerTest, GetStatus_ReturnsTheStatusByte) {
  connect();
  on(request_payload("GET_STATUS"), {reply_payload("GET_STATUS, MEASURE, motor OK")});
  auto status = scanner_->get_status();
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status.status, (p::StatusByte{p::SensorMode::measure, p::MotorMode::ok}));
  EXPECT_EQ(last_sent(), request_payload("GET_STATUS"));
}

TEST_F(ScannerTest, SignalServices_SendSpecBytes) {
  connect();
  on(request_payload("GET_SIGNAL"), {reply_payload("GET_SIGNAL port 0x01")});
  on(request_payload("SET_SIGNAL 0x11 (yellow A + switch 0)"), {reply_payload("SET_SIGNAL accepted")});
  auto port = scanner_->get_signal();
  ASSERT_TRUE(port);
  EXPECT_EQ(*port, 0x0001);
  EXPECT_TRUE(scanner_->set_signal(0x11));
  EXPECT_EQ(last_sent(), request_payload("SET_SIGNAL 0x11 (yellow A + switch 0)"));
}

TEST_F(ScannerTest, SetSignalWithNonZeroResultByte_IsRefused) {
  connect();
  on(request_payload("SET_SIGNAL 0x00"), {Bytes{0x81, 0x05, 0x01, 0x00}});
  auto result = scanner_->set_signal(0);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, ErrorKind::refused);
  EXPECT_EQ(result.error().in_band_code, 0x0100);
}

TEST_F(ScannerTest, ConfigServices_SendSpecBytesAndDecode) {
  connect();
  on(request_payload("SET_CONFIG global id 1, 10 Hz, 0.5°"), {reply_payload("SET_CONFIG success")});
  on(request_payload("GET_CONFIG global"), {reply_payload("GET_CONFIG global (1, 10 Hz, 8 ticks)")});
  on(request_payload("GET_CONFIG Ethernet"),
     {reply_payload("GET_CONFIG Ethernet 192.168.1.10/255.255.255.0/192.168.1.1, node 0, port 0")});
  p::GlobalConfig global;
  global.sensor_id = 1;
  global.motor_speed_hz = 10;
  global.angle_step_ticks = 8;
  EXPECT_TRUE(scanner_->set_config(global));
  EXPECT_EQ(last_sent(), request_payload("SET_CONFIG global id 1, 10 Hz, 0.5°"));
  auto read_global = scanner_->get_global_config();
  ASSERT_TRUE(read_global) << describe(read_global.error());
  EXPECT_EQ(*read_global, global);
  auto ethernet = scanner_->get_ethernet_config();
  ASSERT_TRUE(ethernet) << describe(ethernet.error());
  EXPECT_EQ(ethernet->ip_address, (std::array<std::uint16_t, 4>{192, 168, 1, 10}));
  EXPECT_EQ(ethernet->gateway, (std::array<std::uint16_t, 4>{192, 168, 1, 1}));
}

TEST_F(ScannerTest, OtherConfigKeys_RoundTripThroughTheirTypes) {
  connect();
  const p::CanConfig can{4, 0x6C0, 0x6C1, 0, 0};
  const p::SerialConfig serial{6, 0, 1, 8};
  const p::InterlaceConfig interlace{3};
  on(encoded(p::Request{p::GetConfig{0x0002}}), {encoded(p::Response{p::GetConfigReply{can}})});
  on(encoded(p::Request{p::GetConfig{0x0001}}), {encoded(p::Response{p::GetConfigReply{serial}})});
  on(encoded(p::Request{p::GetConfig{0x0011}}), {encoded(p::Response{p::GetConfigReply{interlace}})});
  auto read_can = scanner_->get_can_config();
  auto read_serial = scanner_->get_serial_config();
  auto read_interlace = scanner_->get_interlace_config();
  ASSERT_TRUE(read_can && read_serial && read_interlace);
  EXPECT_EQ(*read_can, can);
  EXPECT_EQ(*read_serial, serial);
  EXPECT_EQ(*read_interlace, interlace);
}

TEST_F(ScannerTest, GetConfigEchoingAnotherKey_IsUnexpectedReply) {
  connect();
  on(request_payload("GET_CONFIG global"),
     {reply_payload("GET_CONFIG Ethernet 192.168.1.10/255.255.255.0/192.168.1.1, node 0, port 0")});
  auto global = scanner_->get_global_config();
  ASSERT_FALSE(global);
  EXPECT_EQ(global.error().kind, ErrorKind::unexpected_reply);
}

TEST_F(ScannerTest, SetConfigResultNotZero_IsRefusedWithTheResult) {
  connect();
  on(request_payload("SET_CONFIG global id 1, 10 Hz, 0.5°"), {Bytes{0x82, 0x01, 0x00, 0x01}});
  auto result = scanner_->set_config(p::GlobalConfig{1, 10, 8, false});
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, ErrorKind::refused);
  EXPECT_EQ(result.error().in_band_code, p::kSetConfigRefused);
  EXPECT_FALSE(is_retryable(result.error()));
}

TEST_F(ScannerTest, ClockServices_SendSpecBytesAndReturnTheClock) {
  connect();
  on(request_payload("SET_TIME_ABS 1000 ms"), {reply_payload("SET_TIME_ABS → 1000 ms")});
  on(request_payload("SET_TIME_REL −10 ms"), {encoded(p::Response{p::SetTimeRelReply{990}})});
  on(request_payload("GET_SYNC_CLOCK"), {reply_payload("GET_SYNC_CLOCK 0x1234 ms")});
  auto abs = scanner_->set_time_abs(1000);
  auto rel = scanner_->set_time_rel(-10);
  auto clock = scanner_->get_sync_clock();
  ASSERT_TRUE(abs && rel && clock);
  EXPECT_EQ(*abs, 1000);
  EXPECT_EQ(*rel, 990);
  EXPECT_EQ(*clock, 0x1234);
  EXPECT_EQ(log_.sent[1], request_payload("SET_TIME_REL −10 ms"));
}

TEST_F(ScannerTest, SetFilter_SendsSpecBytesAndChecksTheEcho) {
  connect();
  on(request_payload("SET_FILTER near-field on"), {reply_payload("SET_FILTER item 1")});
  on(request_payload("SET_FILTER near-field off"), {Bytes{0x82, 0x09, 0x00, 0x02}});
  EXPECT_TRUE(scanner_->set_filter(true));
  auto off = scanner_->set_filter(false);
  ASSERT_FALSE(off);
  EXPECT_EQ(off.error().kind, ErrorKind::unexpected_reply);
}

TEST_F(ScannerTest, SectorServices_SendSpecBytes) {
  connect();
  on(request_payload("GET_FUNCTION s0"), {reply_payload("GET_FUNCTION s0 normal 270°")});
  on(request_payload("SET_FUNCTION s0 normal 270° temp"), {encoded(p::Response{p::SetFunctionReply{0}})});
  auto sector = scanner_->get_function(0);
  ASSERT_TRUE(sector);
  EXPECT_EQ(*sector, (p::GetFunctionReply{0, 3, 0x10E0}));
  EXPECT_TRUE(scanner_->set_function(p::SetFunction{0, 3, 0x10E0, 0}));
  EXPECT_EQ(last_sent(), request_payload("SET_FUNCTION s0 normal 270° temp"));
}

TEST_F(ScannerTest, SetFunctionInvalid_IsRefusedWithFFFF) {
  connect();
  on(request_payload("SET_FUNCTION s0 normal 270° temp"), {reply_payload("SET_FUNCTION invalid")});
  auto result = scanner_->set_function(p::SetFunction{0, 3, 0x10E0, 0});
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, ErrorKind::refused);
  EXPECT_EQ(result.error().in_band_code, 0xFFFF);
}

TEST_F(ScannerTest, GetFunctionNamingAnotherSector_IsUnexpectedReply) {
  connect();
  on(encoded(p::Request{p::GetFunction{1}}), {reply_payload("GET_FUNCTION s0 normal 270°")});
  auto sector = scanner_->get_function(1);
  ASSERT_FALSE(sector);
  EXPECT_EQ(sector.error().kind, ErrorKind::unexpected_reply);
}

TEST_F(ScannerTest, WriteSectorTable_SendsS1sTableAndTerminator) {
  connect();
  const char* names[] = {"SET_FUNCTION s0 normal 270° temp", "SET_FUNCTION s1 no-meas 314.5° temp",
                         "SET_FUNCTION s2 normal 45° temp", "SET_FUNCTION s3 no-meas 89.5° temp",
                         "SET_FUNCTION s4 not-init 0 temp"};
  for (std::uint16_t i = 0; i < 5; ++i) {
    on(request_payload(names[i]), {encoded(p::Response{p::SetFunctionReply{i}})});
  }
  const SectorDefinition table[] = {{3, 4320}, {1, 5032}, {3, 720}, {1, 1432}};
  auto written = scanner_->write_sector_table(table, /*to_flash=*/false);
  ASSERT_TRUE(written) << describe(written.error());
  ASSERT_EQ(log_.sent.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(log_.sent[i], request_payload(names[i])) << names[i];
  }
}

TEST_F(ScannerTest, WriteSectorTableOfNine_IsInvalidArgument) {
  connect();
  const std::vector<SectorDefinition> table(9);
  auto written = scanner_->write_sector_table(table, true);
  ASSERT_FALSE(written);
  EXPECT_EQ(written.error().kind, ErrorKind::invalid_argument);
  EXPECT_TRUE(log_.sent.empty());
}

TEST_F(ScannerTest, ReadSectorTable_StopsAtTheFirstUninitialisedSector) {
  connect();
  on(request_payload("GET_FUNCTION s0"), {reply_payload("GET_FUNCTION s0 normal 270°")});
  on(encoded(p::Request{p::GetFunction{1}}), {reply_payload("GET_FUNCTION s1 not initialised")});
  auto table = scanner_->read_sector_table();
  ASSERT_TRUE(table);
  ASSERT_EQ(table->size(), 2u);
  EXPECT_EQ((*table)[1].function, p::sector_function::kNotInitialised);
  EXPECT_EQ(log_.sent.size(), 2u);
}

TEST_F(ScannerTest, Transitions_SendSpecBytesAndReturnStatus) {
  connect();
  on(request_payload("TRANS_ROTATE (flash speed)"), {reply_payload("TRANS_ROTATE → ROTATE, motor OK")});
  on(request_payload("TRANS_MEASURE"), {reply_payload("TRANS_MEASURE OK")});
  on(request_payload("TRANS_IDLE"), {reply_payload("TRANS_IDLE → IDLE")});
  auto rotate = scanner_->trans_rotate();
  ASSERT_TRUE(rotate);
  EXPECT_EQ(rotate->status.sensor, p::SensorMode::rotate);
  auto measure = scanner_->trans_measure();
  ASSERT_TRUE(measure);
  EXPECT_EQ(measure->status.sensor, p::SensorMode::measure);
  auto idle = scanner_->trans_idle();
  ASSERT_TRUE(idle);
  EXPECT_EQ(idle->status.sensor, p::SensorMode::idle);
  EXPECT_EQ(log_.sent[0], request_payload("TRANS_ROTATE (flash speed)"));
  EXPECT_EQ(log_.sent[1], request_payload("TRANS_MEASURE"));
  EXPECT_EQ(log_.sent[2], request_payload("TRANS_IDLE"));
}

TEST_F(ScannerTest, TransRotateWithSpeed_SendsTheSpeed) {
  connect();
  on(request_payload("TRANS_ROTATE 10 Hz (layout per S1, non-zero value per S2's semantics)"),
     {reply_payload("TRANS_ROTATE → ROTATE, motor OK")});
  EXPECT_TRUE(scanner_->trans_rotate(10));
}

TEST_F(ScannerTest, TransMeasureRefused_CarriesTheReturnCode) {
  connect();
  on(request_payload("TRANS_MEASURE"), {reply_payload("TRANS_MEASURE refused, code 2")});
  auto measure = scanner_->trans_measure();
  ASSERT_FALSE(measure);
  EXPECT_EQ(measure.error().kind, ErrorKind::refused);
  EXPECT_EQ(measure.error().in_band_code, p::measure_return::kMeanPulseFrequencyTooHigh);
  EXPECT_EQ(measure.error().operation, "TRANS_MEASURE");
}

TEST_F(ScannerTest, DoReset_SendsSpecBytesAndChecksTheEcho) {
  connect();
  on(request_payload("DO_RESET level 2"), {reply_payload("DO_RESET level 2")});
  on(request_payload("DO_RESET level 1"), {reply_payload("DO_RESET level 2")});
  EXPECT_TRUE(scanner_->do_reset(2));
  auto wrong = scanner_->do_reset(1);
  ASSERT_FALSE(wrong);
  EXPECT_EQ(wrong.error().kind, ErrorKind::unexpected_reply);
}

TEST_F(ScannerTest, ProfileStream_DeliversProfilesAndCancelStops) {
  connect();
  on(request_payload("GET_PROFILE stream 0x39FF"), {kProfileRange, kProfileRange});
  on(request_payload("CANCEL_PROFILE"), {kCancelReply});
  start_stream();
  EXPECT_EQ(last_sent(), request_payload("GET_PROFILE stream 0x39FF"));
  for (int i = 0; i < 2; ++i) {
    auto profile = scanner_->next_profile(t0_ + 1s);
    ASSERT_TRUE(profile) << describe(profile.error());
    ASSERT_EQ(profile->sectors.size(), 1u);
    ASSERT_EQ(profile->sectors[0].points.size(), 3u);
    EXPECT_EQ(profile->sectors[0].points[1].distance_q8_m, 0x0280);  // 2.5 m
    EXPECT_EQ(profile->profile_count, 100);
  }
  auto cancelled = scanner_->cancel_profile();
  ASSERT_TRUE(cancelled);
  EXPECT_EQ(cancelled->status.sensor, p::SensorMode::measure);
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
  EXPECT_EQ(last_sent(), request_payload("CANCEL_PROFILE"));
}

TEST_F(ScannerTest, FiniteProfileRequest_ReturnsToConnectedAfterTheLast) {
  connect();
  on(request_payload("GET_PROFILE 1 × 0x39FF"), {kProfileRange});
  start_stream(1);
  EXPECT_EQ(last_sent(), request_payload("GET_PROFILE 1 × 0x39FF"));
  ASSERT_TRUE(scanner_->next_profile(t0_ + 1s));
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
  auto more = scanner_->next_profile(t0_ + 1s);
  ASSERT_FALSE(more);
  EXPECT_EQ(more.error().kind, ErrorKind::wrong_state);
}

TEST_F(ScannerTest, ProfileOfAnotherFormat_IsSkippedAndCounted) {
  connect();
  on(request_payload("GET_PROFILE stream 0x39FF"), {reply_payload(
      "Profile 0x3DFF: same header, 2 points at 180°/180.5°, (1 m, echo 200), (2.5 m, echo 80)"), kProfileRange});
  start_stream();
  auto profile = scanner_->next_profile(t0_ + 1s);
  ASSERT_TRUE(profile);
  EXPECT_EQ(profile->format, p::kFormatRange);
  EXPECT_EQ(scanner_->counters().profiles_skipped, 1u);
}

TEST_F(ScannerTest, NextProfileWithoutStream_IsWrongState) {
  connect();
  auto profile = scanner_->next_profile(t0_ + 1s);
  ASSERT_FALSE(profile);
  EXPECT_EQ(profile.error().kind, ErrorKind::wrong_state);
}

// ------------------------------------------------------------------------ reply matching

TEST_F(ScannerTest, ProfilesArrivingWhileAwaitingAReply_AreQueuedNotLost) {
  connect();
  start_stream();
  // The clock request's reply comes behind two profiles and an unrelated telegram.
  on(request_payload("GET_SYNC_CLOCK"),
     {kProfileRange, kProfileRange, reply_payload("GET_SIGNAL port 0x01"), reply_payload("GET_SYNC_CLOCK 0x1234 ms")});
  auto clock = scanner_->get_sync_clock();
  ASSERT_TRUE(clock) << describe(clock.error());
  EXPECT_EQ(*clock, 0x1234);
  EXPECT_EQ(scanner_->queued_profiles(), 2u);
  EXPECT_EQ(scanner_->counters().skipped_telegrams, 1u);
  const std::size_t receives_before = log_.receive_deadlines.size();
  EXPECT_TRUE(scanner_->next_profile(t0_ + 1s));
  EXPECT_TRUE(scanner_->next_profile(t0_ + 1s));
  EXPECT_EQ(log_.receive_deadlines.size(), receives_before);  // both came from the queue
  EXPECT_EQ(scanner_->counters().profiles_delivered, 2u);
}

TEST_F(ScannerTest, UnrelatedTelegrams_AreSkippedUntilOurReply) {
  connect();
  on(request_payload("GET_SIGNAL"), {Bytes{0x81}, reply_payload("GET_STATUS, IDLE, motor OK"),
                                     failure(0x0203, p::FailureReason::wrong_state),
                                     reply_payload("GET_SIGNAL port 0x01")});
  auto port = scanner_->get_signal();
  ASSERT_TRUE(port);
  EXPECT_EQ(*port, 1);
  EXPECT_EQ(scanner_->counters().skipped_telegrams, 3u);
}

TEST_F(ScannerTest, ServiceFailureNamingOurRequest_IsTypedFinalError) {
  connect();
  on(request_payload("SET_TIME_ABS 1000 ms"), {failure(0x0203, p::FailureReason::wrong_state)});
  auto result = scanner_->set_time_abs(1000);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, ErrorKind::service_failure);
  EXPECT_EQ(result.error().request_code, 0x0203);
  EXPECT_EQ(result.error().failure_reason, p::FailureReason::wrong_state);
  EXPECT_FALSE(is_retryable(result.error()));
  EXPECT_NE(describe(result.error()).find("SET_TIME_ABS fake:scripted"), std::string::npos);
}

TEST_F(ScannerTest, ServiceFailureForGetProfile_SurfacesFromNextProfile) {
  connect();
  on(request_payload("GET_PROFILE stream 0x39FF"), {failure(0x0301, p::FailureReason::out_of_range)});
  start_stream();
  auto profile = scanner_->next_profile(t0_ + 1s);
  ASSERT_FALSE(profile);
  EXPECT_EQ(profile.error().kind, ErrorKind::service_failure);
  EXPECT_EQ(profile.error().failure_reason, p::FailureReason::out_of_range);
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
}

TEST_F(ScannerTest, ServiceFailureForGetProfileWhileAwaitingAnother_IsKeptForNextProfile) {
  connect();
  start_stream();
  on(request_payload("GET_SIGNAL"), {failure(0x0301, p::FailureReason::wrong_state), reply_payload("GET_SIGNAL port 0x01")});
  ASSERT_TRUE(scanner_->get_signal());
  auto profile = scanner_->next_profile(t0_ + 1s);
  ASSERT_FALSE(profile);
  EXPECT_EQ(profile.error().kind, ErrorKind::service_failure);
  EXPECT_EQ(profile.error().request_code, 0x0301);
}

TEST_F(ScannerTest, ReplyThatDoesNotDecode_IsRetryableCorruptedReply) {
  connect();
  on(request_payload("GET_SYNC_CLOCK"), {Bytes{0x82, 0x05, 0x12}});
  auto clock = scanner_->get_sync_clock();
  ASSERT_FALSE(clock);
  EXPECT_EQ(clock.error().kind, ErrorKind::corrupted_reply);
  EXPECT_TRUE(is_retryable(clock.error()));
  EXPECT_EQ(clock.error().decode_detail, p::DecodeError::bad_length);
}

// ------------------------------------------------------------------------------- timeouts

TEST_F(ScannerTest, NoReply_TimesOutAfterFiveSecondsWithOneAttempt) {
  connect();
  script_.erase(request_payload("GET_STATUS"));  // the device stays silent from now on
  auto status = scanner_->get_status();
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().kind, ErrorKind::timeout);
  EXPECT_TRUE(is_retryable(status.error()));
  EXPECT_EQ(status.error().operation, "GET_STATUS");
  EXPECT_EQ(log_.sent.size(), 1u);  // no hidden retry
  ASSERT_FALSE(log_.receive_deadlines.empty());
  EXPECT_EQ(log_.send_deadlines.back(), t0_ + 5s);
  EXPECT_EQ(log_.receive_deadlines.back(), t0_ + 5s);
  EXPECT_EQ(describe(status.error()), "GET_STATUS fake:scripted: timeout: no reply within 5000 ms");
}

TEST_F(ScannerTest, TransRotate_WaitsTenSecondsByDefaultOrAsAsked) {
  connect();
  ASSERT_FALSE(scanner_->trans_rotate());
  EXPECT_EQ(log_.receive_deadlines.back(), t0_ + 10s);
  ASSERT_FALSE(scanner_->trans_rotate(0, 3s));
  EXPECT_EQ(log_.receive_deadlines.back(), t0_ + 3s);
}

TEST_F(ScannerTest, ConfiguredRequestTimeout_IsUsed) {
  ScannerOptions options;
  options.request_timeout = 250ms;
  rebuild(options);
  on(request_payload("GET_STATUS"), {kStatusIdle});
  ASSERT_TRUE(scanner_->connect());
  EXPECT_EQ(log_.receive_deadlines.back(), t0_ + 250ms);
}

TEST_F(ScannerTest, TransportErrorWhileWaiting_IsReturnedUnderTheServiceName) {
  connect();
  on(request_payload("GET_SIGNAL"), {make_error(ErrorKind::connection_closed, "receive", "x", "peer closed")});
  auto port = scanner_->get_signal();
  ASSERT_FALSE(port);
  EXPECT_EQ(port.error().kind, ErrorKind::connection_closed);
  EXPECT_EQ(port.error().operation, "GET_SIGNAL");
  EXPECT_EQ(port.error().object, "fake:scripted");
}

TEST_F(ScannerTest, TransRotateInActive_EndsTheStream) {
  connect();
  start_stream();
  on(request_payload("TRANS_ROTATE (flash speed)"), {reply_payload("TRANS_ROTATE → ROTATE, motor OK")});
  ASSERT_TRUE(scanner_->trans_rotate());
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
}

}  // namespace
}  // namespace ldoem::driver
