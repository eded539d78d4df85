// vectors/: every request of spec 7.1 sent as a payload through the transport, and its reply
// checked against spec 7.2 (or, where 7.2 has no row, against spec 3 and the D-decisions). Each
// case first sends what puts the device into the state its vector needs (7.2's GET_CONFIG
// global shows step 8, so SET_CONFIG global 1/10 Hz/0.5 deg goes first).
#include <map>
#include <optional>

#include "case_steps.hpp"
#include "cases.hpp"

namespace ldoem::conformance {
namespace {

using namespace protocol;
using Handler = std::function<void(Session&, const Bytes&)>;

// D3: the identification texts the emulator sends without a scene override.
std::optional<std::string> d3_identification_text(std::uint16_t item) {
  switch (item) {
    case ident_item::kSensorName: return "LD-OEM1000";
    case ident_item::kFirmwareName: return "ldoem-emud";
    case ident_item::kFirmwareVersion: return LDOEM_VERSION;
    case ident_item::kSensorPartNumber:
    case ident_item::kSensorSerialNumber:
    case ident_item::kEdmSerialNumber:
    case ident_item::kFirmwarePartNumber:
    case ident_item::kApplicationPartNumber: return "0000000";
    default: return std::nullopt;  // sensor version, application name/version: D3 says nothing
  }
}

void identification(Session& session, const Bytes& request) {
  const std::uint16_t item = read_word_be(request, 2);
  const Arrival reply = session.request(request);
  // Spec 3.3: the text starts right after the code; the item is not echoed.
  session.check("GET_IDENTIFICATION reply code", BytePattern::exactly(Bytes{0x81, 0x01}).with_length_rule(LengthRule::at_least),
                reply.payload);
  if (!session.emulator_target()) return;
  if (const auto text = d3_identification_text(item)) {
    Bytes expected{0x81, 0x01};
    expected.insert(expected.end(), text->begin(), text->end());
    session.check("GET_IDENTIFICATION text (D3)", BytePattern::exactly(expected), reply.payload);
    return;
  }
  ByteView text = reply.payload;
  if (text.size() % 2 == 0 && text.back() == 0x00) text = session.without_serial_pad(text, text.size() - 1);
  if (text.size() <= 2) throw CaseFailed("GET_IDENTIFICATION: empty text");
  for (std::size_t i = 2; i < text.size(); ++i) {
    const std::uint8_t c = text[i];
    if (c < 0x20 || c > 0x7E) {
      throw CaseFailed("GET_IDENTIFICATION: byte " + std::to_string(i) + " is not printable ASCII (D3: no NUL, no padding)",
                       "    received: " + format_hex(reply.payload) + "\n");
    }
  }
}

Handler reply_row(std::string row, std::optional<std::chrono::milliseconds> wait = std::nullopt) {
  return [row = std::move(row), wait](Session& session, const Bytes& request) {
    session.expect(row, request, session.pattern(session.reply_vector(row)), wait);
  };
}

void set_signal_then_reset(Session& session, const Bytes& request) {
  session.expect("SET_SIGNAL", request, session.pattern(session.reply_vector("SET_SIGNAL accepted")));
  session.expect("SET_SIGNAL 0", encode_request(SetSignal{0}), session.pattern(session.reply_vector("SET_SIGNAL accepted")));
}

void get_signal(Session& session, const Bytes& request) {
  session.expect("SET_SIGNAL 1", encode_request(SetSignal{0x0001}),
                 session.pattern(session.reply_vector("SET_SIGNAL accepted")));
  session.expect("GET_SIGNAL", request, session.pattern(session.reply_vector("GET_SIGNAL port 0x01")));
  session.expect("SET_SIGNAL 0", encode_request(SetSignal{0}), session.pattern(session.reply_vector("SET_SIGNAL accepted")));
}

void get_config_global(Session& session, const Bytes& request) {
  session.set_global(1, 10, 8);
  session.expect("GET_CONFIG global", request, session.pattern(session.reply_vector("GET_CONFIG global (1, 10 Hz, 8 ticks)")));
}

void get_config_ethernet(Session& session, const Bytes& request) {
  const ReplyVector& row =
      session.reply_vector("GET_CONFIG Ethernet 192.168.1.10/255.255.255.0/192.168.1.1, node 0, port 0");
  if (!session.emulator_target()) {
    // A real LD keeps its own addresses (and changing them would cut a TCP lab off): check the
    // layout only, the key echo and 32 payload bytes (spec 3.4).
    session.expect("GET_CONFIG Ethernet", request, BytePattern::exactly(row.payload).keep_only({0, 1, 2, 3}));
    return;
  }
  const EthernetConfig ethernet{{192, 168, 1, 10}, {255, 255, 255, 0}, {192, 168, 1, 1}, 0, 0};
  session.expect("SET_CONFIG Ethernet", encode_request(SetConfig{ethernet}),
                 BytePattern::exactly(reply_bytes(SetConfigReply{kSetConfigSuccess})));
  session.expect("GET_CONFIG Ethernet", request, row.emulator_pattern());
}

void set_time_rel(Session& session, const Bytes& request) {
  const auto loaded_at = Clock::now();
  session.expect("SET_TIME_ABS 1000", session.request_vector("SET_TIME_ABS 1000 ms"),
                 session.pattern(session.reply_vector("SET_TIME_ABS → 1000 ms")));
  const Arrival reply = session.request(request);
  check_clock_reply(session, "SET_TIME_REL -10", reply_bytes(SetTimeRelReply{990}), reply, loaded_at);
}

void get_sync_clock(Session& session, const Bytes& request) {
  const auto loaded_at = Clock::now();
  session.expect("SET_TIME_ABS 0x1234", encode_request(SetTimeAbs{0x1234}),
                 session.pattern(reply_bytes(SetTimeAbsReply{0x1234}), {0, 1, 2, 3}));
  const Arrival reply = session.request(request);
  check_clock_reply(session, "GET_SYNC_CLOCK", session.reply_vector("GET_SYNC_CLOCK 0x1234 ms").payload, reply, loaded_at);
}

void set_function(Session& session, const Bytes& request) {
  const std::uint16_t sector = read_word_be(request, 2);
  const Arrival reply = session.expect("SET_FUNCTION", request, session.pattern(reply_bytes(SetFunctionReply{sector})));
  // S1 accepts anything but FF FF (spec 3.3); D3 makes it the sector number.
  if (reply.payload.size() >= 4 && read_word_be(reply.payload, 2) == kSetFunctionInvalid) {
    throw CaseFailed("SET_FUNCTION refused with FF FF");
  }
}

// S1's table for areas [90, 270] and [315, 45] deg at 0.5 deg (spec 3.6), the s0..s4 vectors.
void send_s1_sector_table(Session& session) {
  for (const char* name : {"SET_FUNCTION s0 normal 270° temp", "SET_FUNCTION s1 no-meas 314.5° temp",
                           "SET_FUNCTION s2 normal 45° temp", "SET_FUNCTION s3 no-meas 89.5° temp",
                           "SET_FUNCTION s4 not-init 0 temp"}) {
    set_function(session, session.request_vector(name));
  }
}

void get_function_s0(Session& session, const Bytes& request) {
  send_s1_sector_table(session);
  session.expect("GET_FUNCTION s0", request, session.pattern(session.reply_vector("GET_FUNCTION s0 normal 270°")));
}

void get_function_s7(Session& session, const Bytes& request) {
  // The baseline leaves s7 not initialised with stop 0.
  session.expect("GET_FUNCTION s7", request, session.pattern(reply_bytes(GetFunctionReply{7, 0, 0}), {0, 1, 2, 3, 4, 5}));
}

void get_profile_stream(Session& session, const Bytes& request) {
  const std::uint16_t format = read_word_be(request, 4);
  session.enter_rotate();
  session.enter_measure();
  session.send(request);
  for (std::uint16_t sent = 1; sent <= 2; ++sent) {
    const Arrival profile =
        session.await_profile("profile " + std::to_string(sent), session.reply_wait_after(SimMilliseconds(400)));
    check_profile(session, "profile " + std::to_string(sent), baseline_profile(format, sent), profile.payload);
  }
  cancel_profiles(session);
}

void get_profile_once(Session& session, const Bytes& request) {
  const std::uint16_t format = read_word_be(request, 4);
  session.enter_rotate();
  session.enter_measure();
  session.send(request);
  const Arrival profile = session.await_profile("profile 1", session.reply_wait_after(SimMilliseconds(400)));
  check_profile(session, "profile 1", baseline_profile(format, 1), profile.payload);
  // PROFILENUM 1: one profile, then the stream stops by itself (spec 3.5).
  session.expect_silence("after the one profile", revolutions_wall(session, 3, 10) + std::chrono::milliseconds(50));
}

void cancel_profile(Session& session, const Bytes& request) {
  session.enter_rotate();
  session.enter_measure();
  start_profiles(session, 0, kFormatRange);
  session.expect("CANCEL_PROFILE", request, session.pattern(session.reply_vector("CANCEL_PROFILE, MEASURE")));
  // D10: no profile follows the reply.
  session.expect_silence("after the CANCEL_PROFILE reply", revolutions_wall(session, 3, 10) + std::chrono::milliseconds(50));
}

void do_reset_restart(Session& session, const Bytes& request) {
  const std::uint16_t level = read_word_be(request, 2);
  // A temporary sector change (FLASHFLAG 0, no SET_CONFIG global after it) must not survive:
  // D3 says the reset reloads the configuration from flash and clears the clock.
  session.set_sector_table({SetFunction{1, sector_function::kNoMeasurement, 3596, 0}});
  session.enter_rotate();
  const auto reset_at = Clock::now();
  session.expect("DO_RESET", request, BytePattern::exactly(reply_bytes(DoResetReply{level})),
                 session.reply_wait_after(SimMilliseconds(10000)));
  session.expect("GET_STATUS after reset", encode_request(GetStatus{}),
                 BytePattern::exactly(reply_bytes(GetStatusReply{status(SensorMode::idle), {}})));
  session.expect("GET_FUNCTION s1 after reset (flash)", encode_request(GetFunction{1}),
                 BytePattern::exactly(reply_bytes(GetFunctionReply{1, sector_function::kNoMeasurement, 3600})));
  const Arrival clock = session.request(encode_request(GetSyncClock{}));
  check_clock_reply(session, "GET_SYNC_CLOCK after reset (D3: clock 0)", reply_bytes(SyncClockReply{0}), clock, reset_at);
}

void do_reset_halt(Session& session, const Bytes& request) {
  session.enter_rotate();
  session.expect("DO_RESET 2", request, session.pattern(session.reply_vector("DO_RESET level 2")),
                 session.reply_wait_after(SimMilliseconds(10000)));
  session.expect("GET_STATUS", encode_request(GetStatus{}), session.pattern(session.reply_vector("GET_STATUS, IDLE, motor OK")));
}

void trans_idle(Session& session, const Bytes& request) {
  session.enter_rotate();
  session.expect("TRANS_IDLE", request, session.pattern(session.reply_vector("TRANS_IDLE → IDLE")),
                 session.reply_wait_after(SimMilliseconds(10000)));
}

void trans_rotate(Session& session, const Bytes& request) {
  session.expect("TRANS_ROTATE", request, session.pattern(session.reply_vector("TRANS_ROTATE → ROTATE, motor OK")),
                 session.reply_wait_after(SimMilliseconds(10000)));
}

void trans_measure(Session& session, const Bytes& request) {
  session.enter_rotate();
  session.expect("TRANS_MEASURE", request, session.pattern(session.reply_vector("TRANS_MEASURE OK")),
                 session.reply_wait_after(SimMilliseconds(1000)));
}

std::map<std::string, Handler> handlers() {
  std::map<std::string, Handler> table;
  for (const char* item : {"0x00", "0x01", "0x02", "0x03", "0x04", "0x10", "0x11", "0x12", "0x20", "0x21", "0x22"}) {
    table[std::string("GET_IDENTIFICATION ") + item] = identification;
  }
  table["GET_STATUS"] = reply_row("GET_STATUS, IDLE, motor OK");
  table["GET_SIGNAL"] = get_signal;
  table["SET_SIGNAL 0x00"] = set_signal_then_reset;
  table["SET_SIGNAL 0x11 (yellow A + switch 0)"] = set_signal_then_reset;
  table["SET_CONFIG global id 1, 10 Hz, 0.5°"] = reply_row("SET_CONFIG success");
  table["GET_CONFIG global"] = get_config_global;
  table["GET_CONFIG Ethernet"] = get_config_ethernet;
  table["SET_TIME_ABS 1000 ms"] = reply_row("SET_TIME_ABS → 1000 ms");
  table["SET_TIME_REL −10 ms"] = set_time_rel;
  table["GET_SYNC_CLOCK"] = get_sync_clock;
  table["SET_FILTER near-field on"] = reply_row("SET_FILTER item 1");
  table["SET_FILTER near-field off"] = reply_row("SET_FILTER item 1");
  for (const char* name : {"SET_FUNCTION s0 normal 270° temp", "SET_FUNCTION s1 no-meas 314.5° temp",
                           "SET_FUNCTION s2 normal 45° temp", "SET_FUNCTION s3 no-meas 89.5° temp",
                           "SET_FUNCTION s4 not-init 0 temp"}) {
    table[name] = set_function;
  }
  table["GET_FUNCTION s0"] = get_function_s0;
  table["GET_FUNCTION s7"] = get_function_s7;
  table["GET_PROFILE stream 0x39FF"] = get_profile_stream;
  table["GET_PROFILE stream 0x3DFF"] = get_profile_stream;
  table["GET_PROFILE 1 × 0x39FF"] = get_profile_once;
  table["CANCEL_PROFILE"] = cancel_profile;
  table["DO_RESET level 0"] = do_reset_restart;
  table["DO_RESET level 1"] = do_reset_restart;
  table["DO_RESET level 2"] = do_reset_halt;
  table["TRANS_IDLE"] = trans_idle;
  table["TRANS_ROTATE (flash speed)"] = trans_rotate;
  table["TRANS_ROTATE 10 Hz (layout per S1, non-zero value per S2's semantics)"] = trans_rotate;
  table["TRANS_MEASURE"] = trans_measure;
  return table;
}

// Spec 8.9: whether a real LD keeps the TCP session over a full reset or restart is unknown.
bool emulator_only_vector(const std::string& name) { return name == "DO_RESET level 0" || name == "DO_RESET level 1"; }

}  // namespace

void add_vector_cases(std::vector<Case>& cases, const VectorTable& vectors) {
  const auto table = handlers();
  for (const RequestVector& vector : vectors.tcp_requests) {
    const auto found = table.find(vector.name);
    Case c;
    c.name = "vectors/" + slug(vector.name);
    c.emulator_only = emulator_only_vector(vector.name);
    if (found == table.end()) {
      // A new row in tests/vectors must get an expectation here; fail loudly until it does.
      c.run = [name = vector.name](Session&) { throw CaseFailed("no expectation for spec 7.1 vector `" + name + "`"); };
    } else {
      c.run = [handler = found->second, payload = vector.payload](Session& session) { handler(session, payload); };
    }
    cases.push_back(std::move(c));
  }
  // Replies of 7.2 that no request vector above produces.
  cases.push_back(Case{"vectors/GET_STATUS_in_MEASURE",
                       [](Session& session) {
                         session.enter_rotate();
                         session.enter_measure();
                         session.expect("GET_STATUS", encode_request(GetStatus{}),
                                        session.pattern(session.reply_vector("GET_STATUS, MEASURE, motor OK")));
                       },
                       false, true, {}});
  cases.push_back(Case{"vectors/GET_FUNCTION_s1_not_initialised",
                       [](Session& session) {
                         session.set_sector_table({SetFunction{1, sector_function::kNotInitialised, 0, 0}});
                         session.expect("GET_FUNCTION s1", encode_request(GetFunction{1}),
                                        session.pattern(session.reply_vector("GET_FUNCTION s1 not initialised")));
                       },
                       false, true, {}});
}

}  // namespace ldoem::conformance
