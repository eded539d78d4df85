// failures/: every D2 failure reason (SERVICE_FAILURE `FF 00 | code | reason`), the framing
// errors of each transport, and in-band/: the errors a service carries in its own reply
// (SET_CONFIG 0x0001, SET_FUNCTION FF FF, TRANS_MEASURE codes 1..4).
#include "case_steps.hpp"
#include "cases.hpp"
#include "raw_channels.hpp"

namespace ldoem::conformance {
namespace {

using namespace protocol;
using Kinds = std::vector<protocol::Transport>;

void expect_failure(Session& session, std::string_view what, const Bytes& payload, std::uint16_t code,
                    FailureReason reason) {
  session.expect(what, payload, BytePattern::exactly(service_failure(code, reason)));
}

void expect_idle(Session& session, std::string_view what) {
  session.expect(what, encode_request(GetStatus{}), session.pattern(session.reply_vector("GET_STATUS, IDLE, motor OK")));
}

Case failure_case(std::string name, Bytes payload, std::uint16_t code, FailureReason reason, Kinds kinds = {}) {
  return Case{std::move(name),
              [payload = std::move(payload), code, reason](Session& session) {
                expect_failure(session, "SERVICE_FAILURE", payload, code, reason);
                expect_idle(session, "GET_STATUS afterwards");  // nothing changed, still answering
              },
              true, true, std::move(kinds)};
}

// ------------------------------------------------------------------------- framing per transport

void tcp_bad_checksum(Session& session) {
  // Spec 4.1 frame of GET_STATUS with the checksum 0x03 replaced by 0xFF: D2 reason 5, naming
  // the code the broken frame carried. A correct frame afterwards is answered. The suite's own
  // connection is closed meanwhile (a device may take one client at a time); the runner
  // reopens it if this case fails half-way.
  const auto& tcp = std::get<driver::TcpEndpoint>(session.endpoint());
  session.close_transport();
  {
    auto raw = RawTcpSession::connect(tcp, Clock::now() + session.options().reply_timeout);
    if (!raw) throw CaseFailed(raw.error());
    auto roundtrip = [&](std::string_view what, const Bytes& frame, const BytePattern& expected) {
      if (auto written = raw->write(frame); !written) throw CaseFailed(written.error());
      auto reply = raw->receive(Clock::now() + session.options().reply_timeout);
      if (!reply) throw CaseFailed(reply.error());
      if (!*reply) throw CaseFailed(std::string(what) + ": no reply");
      session.check(what, expected, **reply);
    };
    roundtrip("bad checksum", Bytes{0x02, 0x55, 0x53, 0x50, 0x00, 0x00, 0x00, 0x02, 0x01, 0x02, 0xFF},
              BytePattern::exactly(service_failure(0x0102, FailureReason::framing)));
    roundtrip("good frame afterwards", Bytes{0x02, 0x55, 0x53, 0x50, 0x00, 0x00, 0x00, 0x02, 0x01, 0x02, 0x03},
              BytePattern::exactly(session.reply_vector("GET_STATUS, IDLE, motor OK").payload));
  }
  session.reopen_transport();
}

Bytes serial_telegram(std::string_view body) {
  Bytes bytes(body.size() + 2, 0x02);  // STX ... ETX (spec 4.2)
  std::copy(body.begin(), body.end(), bytes.begin() + 1);
  bytes.back() = 0x03;
  return bytes;
}

void serial_raw_then_status(Session& session, std::string_view what, std::string_view body, const BytePattern& expected) {
  auto writer = RawSerialWriter::open(std::get<driver::SerialEndpoint>(session.endpoint()));
  if (!writer) throw CaseFailed(writer.error());
  if (auto written = writer->write(serial_telegram(body)); !written) throw CaseFailed(written.error());
  auto reply = session.receive(Clock::now() + session.options().reply_timeout);
  if (!reply) throw CaseFailed(std::string(what) + ": no reply");
  session.check(what, expected, reply->payload);
  expect_idle(session, "GET_STATUS afterwards");
}

void serial_bad_crc(Session& session) {
  // GET_STATUS (spec 7.4) with CRC 0x0000 instead of 0x6D36.
  serial_raw_then_status(session, "bad CRC", "00100003000001020000",
                         BytePattern::exactly(service_failure(0x0102, FailureReason::framing)));
}

void serial_bad_hex(Session& session) {
  // Which code a telegram with a non-hex digit carried is not reliable: only the reason counts.
  serial_raw_then_status(session, "bad hex", "0010000300000102zz36",
                         BytePattern::exactly(service_failure(0x0102, FailureReason::framing)).with_hole(2, 2));
}

void serial_length_word_mismatch(Session& session) {
  // S2's GET_CONFIG with LLLL 6 announces two parameter WORDs more than it carries: D2 reason 2.
  const SerialVector* vector = session.vectors().serial("GET_CONFIG key 1 (S2's LEN 6)");
  if (vector == nullptr) throw CaseFailed("spec 7.4 vector `GET_CONFIG key 1 (S2's LEN 6)` is missing");
  serial_raw_then_status(session, "LLLL 6 with 4 WORDs", vector->ascii,
                         BytePattern::exactly(service_failure(0x0202, FailureReason::wrong_length)));
}

// D1: a broken ISO-TP sequence is dropped silently; the next correct request is answered.
void can_frames_then_silence(Session& session, const std::vector<Bytes>& frames, std::chrono::milliseconds silence) {
  auto writer = RawCanWriter::open(std::get<driver::CanEndpoint>(session.endpoint()));
  if (!writer) throw CaseFailed(writer.error());
  for (const Bytes& frame : frames) {
    if (auto written = writer->write_frame(frame); !written) throw CaseFailed(written.error());
  }
  session.expect_silence("after the broken ISO-TP sequence", silence);
  expect_idle(session, "GET_STATUS afterwards");
}

// SET_CONFIG global 1/10 Hz/4 ticks (10 bytes): first frame with 6 bytes, then 4 in a CF.
const Bytes kFirstFrame{0x10, 0x0A, 0x02, 0x01, 0x00, 0x10, 0x00, 0x01};

void can_wrong_sequence_number(Session& session) {
  can_frames_then_silence(session, {kFirstFrame, Bytes{0x22, 0x00, 0x0A, 0x00, 0x04}}, std::chrono::milliseconds(500));
}

void can_unexpected_consecutive_frame(Session& session) {
  can_frames_then_silence(session, {Bytes{0x21, 0x00, 0x0A, 0x00, 0x04}}, std::chrono::milliseconds(500));
}

void can_first_frame_timeout(Session& session) {
  // N_Cr = 1000 ms (D1): after it, the partial telegram is gone and nothing was answered.
  can_frames_then_silence(session, {kFirstFrame}, std::chrono::milliseconds(1500));
}

// ------------------------------------------------------------------------------------- in-band

Bytes measure_refused(std::uint16_t code) {
  return reply_bytes(TransMeasureReply{status(SensorMode::rotate), code});
}

void trans_measure_refused(Session& session, std::uint16_t code) {
  session.enter_rotate();
  session.expect("TRANS_MEASURE", encode_request(TransMeasure{}), session.pattern(measure_refused(code), {0, 1, 6, 7}),
                 session.reply_wait_after(SimMilliseconds(1000)));
  // Spec 3.3 [I]: a refused device stays in ROTATE.
  session.expect("GET_STATUS", encode_request(GetStatus{}),
                 session.pattern(reply_bytes(GetStatusReply{status(SensorMode::rotate), {}}), {0, 1, 5}));
}

void set_config_refused(Session& session, const GlobalConfig& config) {
  const Arrival reply = session.expect("SET_CONFIG global", encode_request(SetConfig{config}),
                                       session.pattern(reply_bytes(SetConfigReply{kSetConfigRefused}), {0, 1}));
  // Spec 3.3 [C]: anything but 0x0000 is a refusal.
  if (reply.payload.size() >= 4 && read_word_be(reply.payload, 2) == kSetConfigSuccess) {
    throw CaseFailed("SET_CONFIG global accepted " + std::to_string(config.motor_speed_hz) + " Hz / " +
                     std::to_string(config.angle_step_ticks) + " ticks");
  }
  session.expect("GET_CONFIG global unchanged", encode_request(GetConfig{key_word(ConfigKey::global)}),
                 session.pattern(reply_bytes(GetConfigReply{GlobalConfig{1, 10, 4, false}}), {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
}

}  // namespace

void add_failure_cases(std::vector<Case>& cases) {
  // Reason 1: unknown service code, or a code whose layout nobody published.
  cases.push_back(failure_case("failures/unknown_service_0x0500", {0x05, 0x00}, 0x0500, FailureReason::unknown_service));
  cases.push_back(failure_case("failures/unknown_service_0x0103", {0x01, 0x03}, 0x0103, FailureReason::unknown_service));
  cases.push_back(failure_case("failures/unknown_service_response_code_0x8102", {0x81, 0x02}, 0x8102,
                               FailureReason::unknown_service));
  for (std::uint16_t code : {0x0106, 0x0601, 0x0701, 0x0801}) {
    char name[64];
    std::snprintf(name, sizeof name, "failures/unpublished_layout_0x%04X", code);
    cases.push_back(failure_case(name, {static_cast<std::uint8_t>(code >> 8), static_cast<std::uint8_t>(code)}, code,
                                 FailureReason::unknown_service));
  }
  // Reason 2: missing or surplus parameter WORDs (one trailing 0x0000 is accepted).
  cases.push_back(failure_case("failures/wrong_length_GET_STATUS_two_surplus_words", {0x01, 0x02, 0x00, 0x00, 0x00, 0x00},
                               0x0102, FailureReason::wrong_length));
  cases.push_back(failure_case("failures/wrong_length_SET_TIME_ABS_without_time", {0x02, 0x03}, 0x0203,
                               FailureReason::wrong_length));
  cases.push_back(failure_case("failures/wrong_length_GET_FUNCTION_without_sector", {0x02, 0x0B}, 0x020B,
                               FailureReason::wrong_length));
  cases.push_back(failure_case("failures/wrong_length_SET_FILTER_one_word_short", {0x02, 0x09, 0x00, 0x01}, 0x0209,
                               FailureReason::wrong_length));
  // Odd lengths and a lone byte exist only where the transport carries bytes (serial pads WORDs).
  cases.push_back(failure_case("failures/wrong_length_GET_STATUS_odd_byte", {0x01, 0x02, 0x00}, 0x0102,
                               FailureReason::wrong_length, {protocol::Transport::tcp, protocol::Transport::can}));
  cases.push_back(failure_case("failures/wrong_length_no_room_for_a_code", {0x01}, 0x0000, FailureReason::wrong_length,
                               {protocol::Transport::tcp, protocol::Transport::can}));
  cases.push_back(Case{"failures/trailing_zero_word_accepted",
                       [](Session& session) {
                         session.expect("GET_STATUS + 0x0000", Bytes{0x01, 0x02, 0x00, 0x00},
                                        session.pattern(session.reply_vector("GET_STATUS, IDLE, motor OK")));
                       },
                       true, true, {}});
  // Reason 3 is covered state by state in states/; one representative here.
  cases.push_back(failure_case("failures/wrong_state_GET_PROFILE_in_IDLE", encode_request(GetProfile{0, kFormatRange}),
                               0x0301, FailureReason::wrong_state));
  // Reason 4: a parameter out of range where the service has no in-band error.
  cases.push_back(failure_case("failures/out_of_range_TRANS_ROTATE_3_Hz", encode_request(TransRotate{3}), 0x0403,
                               FailureReason::out_of_range));
  cases.push_back(failure_case("failures/out_of_range_TRANS_ROTATE_21_Hz", encode_request(TransRotate{21}), 0x0403,
                               FailureReason::out_of_range));
  cases.push_back(failure_case("failures/out_of_range_GET_FUNCTION_s8", encode_request(GetFunction{8}), 0x020B,
                               FailureReason::out_of_range));
  cases.push_back(failure_case("failures/out_of_range_DO_RESET_level_3", encode_request(DoReset{3}), 0x0401,
                               FailureReason::out_of_range));
  cases.push_back(failure_case("failures/out_of_range_GET_IDENTIFICATION_item_5", encode_request(GetIdentification{5}),
                               0x0101, FailureReason::out_of_range));
  cases.push_back(failure_case("failures/out_of_range_SET_FILTER_item_2", encode_request(SetFilter{2, 1}), 0x0209,
                               FailureReason::out_of_range));
  // Reason 5 and D1: framing, per transport.
  cases.push_back(Case{"failures/framing_tcp_bad_checksum", tcp_bad_checksum, true, true, {protocol::Transport::tcp}});
  cases.push_back(Case{"failures/framing_serial_bad_crc", serial_bad_crc, true, true, {protocol::Transport::serial}});
  cases.push_back(Case{"failures/framing_serial_bad_hex", serial_bad_hex, true, true, {protocol::Transport::serial}});
  cases.push_back(Case{"failures/framing_serial_length_word_mismatch", serial_length_word_mismatch, true, true,
                       {protocol::Transport::serial}});
  cases.push_back(Case{"failures/framing_can_wrong_sequence_number_dropped", can_wrong_sequence_number, true, true,
                       {protocol::Transport::can}});
  cases.push_back(Case{"failures/framing_can_unexpected_consecutive_frame_dropped", can_unexpected_consecutive_frame, true,
                       true, {protocol::Transport::can}});
  cases.push_back(Case{"failures/framing_can_first_frame_timeout_dropped", can_first_frame_timeout, true, true,
                       {protocol::Transport::can}});

  // In-band errors (spec 3.3 [C] for the codes; D2 for the values).
  cases.push_back(Case{"in-band/SET_CONFIG_speed_25_Hz_refused",
                       [](Session& session) { set_config_refused(session, GlobalConfig{1, 25, 4, false}); }, false, true, {}});
  cases.push_back(Case{"in-band/SET_CONFIG_speed_4_Hz_refused",
                       [](Session& session) { set_config_refused(session, GlobalConfig{1, 4, 4, false}); }, false, true, {}});
  cases.push_back(Case{"in-band/SET_CONFIG_step_7_ticks_refused",  // 7 does not divide 5760 (spec 3.4)
                       [](Session& session) { set_config_refused(session, GlobalConfig{1, 10, 7, false}); }, false, true, {}});
  cases.push_back(Case{"in-band/SET_FUNCTION_sector_8_invalid",
                       [](Session& session) {
                         session.expect("SET_FUNCTION s8", encode_request(SetFunction{8, 3, 2160, 0}),
                                        session.pattern(session.reply_vector("SET_FUNCTION invalid")));
                       },
                       false, true, {}});
  cases.push_back(Case{"in-band/SET_FUNCTION_stop_above_360_deg_invalid",  // spec 3.6: stop <= 5760
                       [](Session& session) {
                         session.expect("SET_FUNCTION s0 stop 5764", encode_request(SetFunction{0, 3, 5764, 0}),
                                        session.pattern(session.reply_vector("SET_FUNCTION invalid")));
                       },
                       true, true, {}});
  // TRANS_MEASURE codes (spec 5 pulse rules: max = 5760/step * f <= 14400 Hz, mean = max *
  // area/5760 <= 10800 Hz with area = stop - previous stop).
  cases.push_back(Case{"in-band/TRANS_MEASURE_code_1_max_pulse_20_Hz_at_0.25_deg",
                       [](Session& session) {
                         session.set_global(1, 20, 4);  // 1440 * 20 = 28800 Hz
                         trans_measure_refused(session, measure_return::kMaxPulseFrequencyTooHigh);
                       },
                       false, true, {}});
  cases.push_back(Case{"in-band/TRANS_MEASURE_code_2_mean_pulse",
                       [](Session& session) {
                         // s1 stop 3596: s0 covers 4324 ticks, 14400 * 4324/5760 = 10810 Hz.
                         session.set_sector_table({SetFunction{1, sector_function::kNoMeasurement, 3596, 0}});
                         session.enter_rotate();
                         session.expect("TRANS_MEASURE", encode_request(TransMeasure{}),
                                        session.pattern(session.reply_vector("TRANS_MEASURE refused, code 2")),
                                        session.reply_wait_after(SimMilliseconds(1000)));
                       },
                       false, true, {}});
  cases.push_back(Case{"in-band/TRANS_MEASURE_code_3_no_sector",
                       [](Session& session) {
                         session.set_sector_table({SetFunction{0, sector_function::kNotInitialised, 0, 0},
                                                   SetFunction{1, sector_function::kNotInitialised, 0, 0}});
                         trans_measure_refused(session, measure_return::kSectorBordersNotConfigured);
                       },
                       false, true, {}});
  cases.push_back(Case{"in-band/TRANS_MEASURE_code_3_stops_wrap_twice",
                       [](Session& session) {
                         // Stops 2160, 1000, 3000, 500 go round the circle twice (spec 3.6: once).
                         session.set_sector_table({SetFunction{1, sector_function::kNoMeasurement, 1000, 0},
                                                   SetFunction{2, sector_function::kNoMeasurement, 3000, 0},
                                                   SetFunction{3, sector_function::kNoMeasurement, 500, 0}});
                         trans_measure_refused(session, measure_return::kSectorBordersNotConfigured);
                       },
                       false, true, {}});
  cases.push_back(Case{"in-band/TRANS_MEASURE_code_4_stop_not_multiple_of_step",
                       [](Session& session) {
                         // s1 stop 3602 at 4 ticks; s0 then covers 4318 ticks = 10795 Hz mean.
                         session.set_sector_table({SetFunction{1, sector_function::kNoMeasurement, 3602, 0}});
                         trans_measure_refused(session, measure_return::kSectorBordersNotMultipleOfStep);
                       },
                       false, true, {}});
}

}  // namespace ldoem::conformance
