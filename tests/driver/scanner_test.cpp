// Scanner over a scripted transport: the lifecycle, and every service's request bytes from spec
// 7.1 with replies from spec 7.2 (or protocol's encoder where the spec has no row) and its D2
// failures. Profile streams, reply matching and timeouts: scanner_replies_test.cpp.
#include "ldoem/driver/scanner.hpp"

#include <gtest/gtest.h>

#include "scanner_test_fixture.hpp"
#include "test_support.hpp"

namespace ldoem::driver {
namespace {

namespace p = protocol;
using namespace scanner_test;
using test::encoded;
using test::kStatusIdle;

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

}  // namespace
}  // namespace ldoem::driver
