// conversation/: the two public drivers' whole conversations, as a real host would hold them.
// S1 (spec 7.3, Ethernet driver) at payload level over any transport; S2 (spec 7.4, serial
// driver) with its exact telegrams when the transport is serial, at payload level otherwise.
#include <optional>

#include "case_steps.hpp"
#include "cases.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "raw_channels.hpp"

namespace ldoem::conformance {
namespace {

using namespace protocol;

BytePattern code_only(std::uint16_t code) {
  Bytes bytes;
  append_word_be(bytes, code);
  return BytePattern::exactly(bytes).with_length_rule(LengthRule::at_least);
}

void s1_conversation(Session& session) {
  // 1. GET_STATUS: IDLE (the baseline), so S1 goes straight on.
  session.expect("1 GET_STATUS", encode_request(GetStatus{}), session.pattern(session.reply_vector("GET_STATUS, IDLE, motor OK")));
  // 2. All eleven identification items, in the table's order.
  for (std::uint16_t item : {0x00, 0x01, 0x02, 0x03, 0x04, 0x10, 0x11, 0x12, 0x20, 0x21, 0x22}) {
    session.expect("2 GET_IDENTIFICATION " + std::to_string(item), encode_request(GetIdentification{item}), code_only(0x8101));
  }
  // 3. Ethernet configuration: key echo and the 32-byte layout (spec 3.4).
  Bytes ethernet_layout(32, 0x00);
  ethernet_layout[0] = 0x82;
  ethernet_layout[1] = 0x02;
  ethernet_layout[3] = 0x05;
  session.expect("3 GET_CONFIG 0x05", encode_request(GetConfig{key_word(ConfigKey::ethernet)}),
                 BytePattern::exactly(ethernet_layout).keep_only({0, 1, 2, 3}));
  // 4. Global configuration: the baseline 1 / 10 Hz / 4 ticks.
  session.expect("4 GET_CONFIG 0x10", encode_request(GetConfig{key_word(ConfigKey::global)}),
                 session.pattern(reply_bytes(GetConfigReply{GlobalConfig{1, 10, 4, false}}), {0, 1, 2, 3}));
  // 5. The sector table until a sector with function 0.
  const std::vector<SetFunction> table = baseline_sector_table();
  for (const SetFunction& sector : table) {
    session.expect("5 GET_FUNCTION " + std::to_string(sector.sector), encode_request(GetFunction{sector.sector}),
                   session.pattern(reply_bytes(GetFunctionReply{sector.sector, sector.function, sector.stop_ticks}),
                                   {0, 1, 2, 3}));
  }
  // 6. SET_SIGNAL 0, 7. TRANS_ROTATE 0, 8. TRANS_MEASURE.
  session.expect("6 SET_SIGNAL 0", encode_request(SetSignal{0}), session.pattern(session.reply_vector("SET_SIGNAL accepted")));
  session.expect("7 TRANS_ROTATE 0", encode_request(TransRotate{0}),
                 session.pattern(session.reply_vector("TRANS_ROTATE → ROTATE, motor OK")),
                 session.reply_wait_after(SimMilliseconds(10000)));
  session.expect("8 TRANS_MEASURE", encode_request(TransMeasure{}), session.pattern(session.reply_vector("TRANS_MEASURE OK")),
                 session.reply_wait_after(SimMilliseconds(1000)));
  // 9. GET_PROFILE stream 0x39FF; S1 wants a MEASURE/OK profile at least every second (spec 6).
  session.send(encode_request(GetProfile{0, kFormatRange}));
  std::optional<Clock::time_point> previous;
  for (std::uint16_t sent = 1; sent <= 5; ++sent) {
    const std::string what = "9 profile " + std::to_string(sent);
    const Arrival profile = session.await_profile(what, previous ? std::chrono::milliseconds(1000)
                                                                 : session.reply_wait_after(SimMilliseconds(400)));
    check_profile(session, what, baseline_profile(kFormatRange, sent), profile.payload);
    previous = profile.at;
  }
  // 10. CANCEL_PROFILE: still MEASURE, so 11. TRANS_ROTATE 0, 12. TRANS_IDLE, 13. SET_SIGNAL 0.
  cancel_profiles(session);
  session.expect("11 TRANS_ROTATE 0", encode_request(TransRotate{0}),
                 session.pattern(session.reply_vector("TRANS_ROTATE → ROTATE, motor OK")),
                 session.reply_wait_after(SimMilliseconds(10000)));
  session.expect("12 TRANS_IDLE", encode_request(TransIdle{}), session.pattern(session.reply_vector("TRANS_IDLE → IDLE")));
  session.expect("13 SET_SIGNAL 0", encode_request(SetSignal{0}), session.pattern(session.reply_vector("SET_SIGNAL accepted")));
}

// The payload inside an S2 telegram: WORDs after address, length and package id, before the CRC.
Bytes payload_of(const SerialVector& vector) {
  const auto words = parse_hex(vector.ascii);
  if (!words || words->size() < 10) throw CaseFailed("serial vector `" + vector.name + "` is not a telegram");
  return Bytes(words->begin() + 6, words->end() - 2);
}

// Sends one of S2's telegrams: its exact bytes on a serial line, its payload elsewhere.
class S2Sender {
 public:
  explicit S2Sender(Session& session) : session_(session) {
    if (const auto* serial = std::get_if<driver::SerialEndpoint>(&session.endpoint())) {
      auto writer = RawSerialWriter::open(*serial);
      if (!writer) throw CaseFailed(writer.error());
      writer_.emplace(std::move(*writer));
    }
  }

  Arrival send(const SerialVector& vector, std::chrono::milliseconds wait) {
    return send_bytes(vector.telegram(), payload_of(vector), wait);
  }
  // A telegram S2 would build the same way but that spec 7.4 does not list.
  Arrival send(const Request& request, std::chrono::milliseconds wait) {
    const Bytes payload = encode_request(request);
    return send_bytes(encode_serial_request(payload), payload, wait);
  }

 private:
  Arrival send_bytes(const Bytes& telegram, const Bytes& payload, std::chrono::milliseconds wait) {
    if (!writer_) return session_.request(payload, wait);
    auto written = writer_->write(telegram);
    if (!written) throw CaseFailed(written.error());
    const Deadline deadline = Clock::now() + wait;
    while (auto arrival = session_.receive(deadline)) {
      if (arrival->payload.size() < 2 || read_word_be(arrival->payload, 0) != 0x8301) return std::move(*arrival);
    }
    throw CaseFailed("no reply to " + format_hex(payload) + " within " + std::to_string(wait.count()) + " ms");
  }

  Session& session_;
  std::optional<RawSerialWriter> writer_;
};

const SerialVector& serial_vector(Session& session, std::string_view name) {
  const SerialVector* vector = session.vectors().serial(name);
  if (vector == nullptr) throw CaseFailed("spec 7.4 vector `" + std::string(name) + "` is missing");
  return *vector;
}

void s2_conversation(Session& session) {
  S2Sender s2(session);
  const auto wait = session.options().reply_timeout;
  const auto spin_wait = session.reply_wait_after(SimMilliseconds(10000));
  Arrival reply = s2.send(serial_vector(session, "GET_IDENTIFICATION item 1 (S2's default)"), wait);
  session.check("GET_IDENTIFICATION 1", code_only(0x8101), reply.payload);
  reply = s2.send(serial_vector(session, "DO_RESET 2"), spin_wait);
  session.check("DO_RESET 2", session.pattern(session.reply_vector("DO_RESET level 2")), reply.payload);
  reply = s2.send(serial_vector(session, "SET_CONFIG RS-232 115200 8N1"), wait);
  session.check("SET_CONFIG RS-232", session.pattern(session.reply_vector("SET_CONFIG success")), reply.payload);
  reply = s2.send(serial_vector(session, "SET_CONFIG global id 0x10, 10 Hz, 0.5°, pad 0"), wait);
  session.check("SET_CONFIG global (S2)", session.pattern(session.reply_vector("SET_CONFIG success")), reply.payload);
  // Eight SET_FUNCTION to flash; S2 does not look at the replies (spec 3.6: the LD tolerated
  // stop 0xFFF0 or its error went unnoticed), so only the code is checked.
  reply = s2.send(serial_vector(session, "SET_FUNCTION s0 normal 359° flash"), wait);
  session.check("SET_FUNCTION s0", code_only(0x820A), reply.payload);
  reply = s2.send(serial_vector(session, "SET_FUNCTION s1 not-init stop 0xFFF0 flash"), wait);
  session.check("SET_FUNCTION s1", code_only(0x820A), reply.payload);
  for (std::uint16_t sector = 2; sector < kSectorCount; ++sector) {
    reply = s2.send(SetFunction{sector, sector_function::kNotInitialised, 0xFFF0, 1}, wait);
    session.check("SET_FUNCTION s" + std::to_string(sector), code_only(0x820A), reply.payload);
  }
  reply = s2.send(TransRotate{10}, spin_wait);  // S2 sends the configured 10 Hz
  session.check("TRANS_ROTATE 10", session.pattern(session.reply_vector("TRANS_ROTATE → ROTATE, motor OK")), reply.payload);
  reply = s2.send(serial_vector(session, "TRANS_MEASURE (+ 0x0000)"), session.reply_wait_after(SimMilliseconds(1000)));
  session.check("TRANS_MEASURE", session.pattern(session.reply_vector("TRANS_MEASURE OK")), reply.payload);
  reply = s2.send(serial_vector(session, "SET_SIGNAL 0x0001"), wait);
  session.check("SET_SIGNAL 1", session.pattern(session.reply_vector("SET_SIGNAL accepted")), reply.payload);
  // GET_PROFILE 1 x 0x0700, repeated after every profile: one sector from 359.5 deg round to
  // 359 deg at 0.5 deg = 720 points, counted from the telegram length (no POINTNUM).
  ProfileExpectation expected;
  expected.format = 0x0700;
  expected.sectors = expected_sectors({SetFunction{0, sector_function::kNormalMeasurement, 5744, 1},
                                       SetFunction{1, sector_function::kNotInitialised, 0xFFF0, 1}},
                                      8);
  const SerialVector& get_profile = serial_vector(session, "GET_PROFILE 1 × 0x0700");
  for (int round = 1; round <= 3; ++round) {
    const std::string what = "GET_PROFILE 1 x 0x0700, round " + std::to_string(round);
    if (const auto* serial = std::get_if<driver::SerialEndpoint>(&session.endpoint()); serial != nullptr) {
      auto writer = RawSerialWriter::open(*serial);
      if (!writer) throw CaseFailed(writer.error());
      if (auto written = writer->write(get_profile.telegram()); !written) throw CaseFailed(written.error());
    } else {
      session.send(payload_of(get_profile));
    }
    const Arrival profile = session.await_profile(what, session.reply_wait_after(SimMilliseconds(400)));
    check_profile(session, what, expected, profile.payload);
  }
  reply = s2.send(serial_vector(session, "DO_RESET 2"), spin_wait);
  session.check("DO_RESET 2 at the end", session.pattern(session.reply_vector("DO_RESET level 2")), reply.payload);
}

}  // namespace

void add_conversation_cases(std::vector<Case>& cases) {
  cases.push_back(Case{"conversation/S1", s1_conversation, false, true, {}});
  cases.push_back(Case{"conversation/S2", s2_conversation, false, true, {}});
}

}  // namespace ldoem::conformance
