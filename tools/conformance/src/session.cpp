#include "session.hpp"

#include <cmath>
#include <iostream>
#include <thread>

#include "ldoem/driver/error.hpp"
#include "ldoem/protocol/text.hpp"
#include "recording_transport.hpp"

namespace ldoem::conformance {
namespace {

using namespace protocol;

constexpr std::uint16_t kProfileCode = 0x8301;  // spec 3.5

// A host that does not read for this long can lose CAN frames: vcan in User-Mode Linux carries
// about 6 000 frames/s and the receive buffer holds about a thousand (conformance.md).
constexpr double kLinkStallToleranceMs = 200;

bool is_profile(ByteView payload) { return payload.size() >= 2 && read_word_be(payload, 0) == kProfileCode; }

std::string describe_request(ByteView payload) { return format_telegram(payload); }

// D4 sector table: s0 normal measurement to 135 deg, s1 no measurement to 225 deg, rest unused.
constexpr std::uint16_t kBaselineStepTicks = 4;
constexpr std::uint16_t kBaselineSpeedHz = 10;
constexpr std::uint16_t kBaselineSensorId = 1;

}  // namespace

Bytes reply_bytes(const Response& response) { return encode_response(response); }

StatusBlock status(SensorMode sensor, MotorMode motor) { return make_status_block(sensor, motor); }

Bytes service_failure(std::uint16_t request_code, FailureReason reason) {
  return encode_response(ServiceFailure{request_code, reason});
}

Session::Session(std::unique_ptr<driver::TelegramTransport> transport, const SuiteOptions& options, const VectorTable& vectors)
    : transport_(std::move(transport)), options_(options), vectors_(vectors) {}

void Session::log(const char* direction, ByteView payload) const {
  if (!options_.verbose) return;
  std::cerr << direction << ' ' << format_telegram(payload.size() > 64 ? payload.first(64) : payload)
            << (payload.size() > 64 ? " ..." : "") << '\n';
}

void Session::note_request(ByteView payload) {
  auto request = decode_request(payload);
  if (!request) return;
  if (std::holds_alternative<GetProfile>(*request)) {
    device_clock_.start_stream();
    dropped_at_stream_start_ = transport_->counters().dropped_frames;
    missing_in_stream_ = 0;
  }
  if (const auto* rotate = std::get_if<TransRotate>(&*request)) pending_rotate_hz_ = rotate->frequency_hz;
  if (const auto* config = std::get_if<SetConfig>(&*request)) {
    if (const auto* global = std::get_if<GlobalConfig>(&config->body)) pending_config_hz_ = global->motor_speed_hz;
  }
}

void Session::note_reply(ByteView payload) {
  auto response = decode_response(payload);
  if (!response) return;
  if (const auto* config = std::get_if<SetConfigReply>(&*response)) {
    if (config->value == kSetConfigSuccess && pending_config_hz_) configured_hz_ = *pending_config_hz_;
    pending_config_hz_.reset();
  } else if (std::holds_alternative<TransRotateReply>(*response)) {
    const std::uint16_t asked = pending_rotate_hz_.value_or(0);
    device_clock_.set_speed_hz(asked != 0 ? asked : configured_hz_);
    pending_rotate_hz_.reset();
  } else if (std::holds_alternative<DoResetReply>(*response)) {
    device_clock_.set_speed_hz(configured_hz_);  // the next TRANS_ROTATE 0 turns at the configured speed
  }
}

void Session::send(ByteView payload) {
  log(">>", payload);
  note_request(payload);
  auto sent = transport_->send(payload, Clock::now() + options_.reply_timeout);
  if (!sent) throw CaseFailed("send " + describe_request(payload) + ": " + driver::describe(sent.error()));
}

std::optional<Arrival> Session::receive(Deadline deadline) {
  auto received = transport_->receive(deadline);
  if (!received) {
    if (received.error().kind == driver::ErrorKind::timeout) return std::nullopt;
    throw CaseFailed("receive: " + driver::describe(received.error()));
  }
  const Clock::time_point at = Clock::now();
  log("<<", *received);
  if (!is_profile(*received)) {
    note_reply(*received);
  } else if (auto profile = decode_profile(*received)) {  // one that does not decode fails its case's check
    // Broken telegrams the transport dropped in this stream (a CAN link that lost frames or timed
    // out, D1) may have been profiles: PROFILESENT may skip that many, the clock may not. The
    // transport counts a drop when it reads the frames, which can be before it hands up the
    // profiles read with them, so the drops are counted per stream, not per profile.
    const std::uint64_t dropped = transport_->counters().dropped_frames - dropped_at_stream_start_;
    const std::uint64_t lost = dropped > missing_in_stream_ ? dropped - missing_in_stream_ : 0;
    if (auto slipped = device_clock_.next(*profile, lost)) throw CaseFailed("device clock: " + *slipped);
    if (device_clock_.last_sent_step() > 1) {
      missing_in_stream_ += device_clock_.last_sent_step() - 1u;
      // The host link's failure, not the device's: judged like a wall-clock one (a starved host
      // reads too late and loses frames), INCONCLUSIVE when the probe saw the machine stall.
      throw WallClockFailed("link: PROFILESENT advanced " + std::to_string(device_clock_.last_sent_step()) +
                                " to " + std::to_string(profile->profile_sent) + " and the transport dropped " +
                                std::to_string(dropped) + " broken telegram(s) in this stream; the device clock was exact",
                            kLinkStallToleranceMs);
    }
  }
  return Arrival{std::move(*received), at};
}

Arrival Session::request(ByteView payload, std::optional<std::chrono::milliseconds> wait) {
  const auto waited = wait.value_or(options_.reply_timeout);
  send(payload);
  const Deadline deadline = Clock::now() + waited;
  while (true) {
    auto arrival = receive(deadline);
    if (!arrival) {
      throw WallClockFailed("no reply to " + describe_request(payload) + " within " + std::to_string(waited.count()) + " ms",
                            static_cast<double>(waited.count()));
    }
    if (!is_profile(arrival->payload)) return std::move(*arrival);
    ++profiles_skipped_;
  }
}

ByteView Session::without_serial_pad(ByteView received, std::size_t expected_size) const {
  // Spec 4.2 carries whole WORDs only, so an odd payload (a GET_IDENTIFICATION text) arrives
  // with one 0x00 pad byte (protocol/serial_framing.hpp); the host cannot tell it from text.
  const bool serial = std::holds_alternative<driver::SerialEndpoint>(endpoint());
  if (serial && expected_size % 2 == 1 && received.size() == expected_size + 1 && received.back() == 0x00) {
    return received.first(expected_size);
  }
  return received;
}

void Session::check(std::string_view what, const BytePattern& expected, ByteView received_telegram) {
  const ByteView received = without_serial_pad(received_telegram, expected.bytes.size());
  const auto mismatch = compare(expected, received);
  if (!mismatch) return;
  std::string why = std::string(what) + ": reply differs";
  if (mismatch->length_differs) {
    why += " (" + std::to_string(received.size()) + " bytes, expected " +
           (expected.length_rule == LengthRule::at_least ? "at least " : "") + std::to_string(expected.bytes.size()) + ")";
  }
  why += " [received: " + format_telegram(received.size() > 32 ? received.first(32) : received) +
         (received.size() > 32 ? " ..." : "") + "]";
  throw CaseFailed(why, render_diff(expected, received, *mismatch));
}

Arrival Session::expect(std::string_view what, ByteView payload, const BytePattern& reply,
                        std::optional<std::chrono::milliseconds> wait) {
  Arrival arrival = request(payload, wait);
  check(what, reply, arrival.payload);
  return arrival;
}

Arrival Session::await_profile(std::string_view what, std::chrono::milliseconds wait) {
  auto arrival = receive(Clock::now() + wait);
  if (!arrival) {
    throw WallClockFailed(std::string(what) + ": no profile within " + std::to_string(wait.count()) + " ms",
                          static_cast<double>(wait.count()));
  }
  if (!is_profile(arrival->payload)) {
    throw CaseFailed(std::string(what) + ": expected a profile (0x8301), received " + format_telegram(arrival->payload));
  }
  return std::move(*arrival);
}

void Session::expect_silence(std::string_view what, std::chrono::milliseconds wall) {
  auto arrival = receive(Clock::now() + wall);
  if (arrival) {
    throw CaseFailed(std::string(what) + ": expected nothing for " + std::to_string(wall.count()) + " ms, received " +
                     format_telegram(arrival->payload.size() > 32 ? ByteView(arrival->payload).first(32)
                                                                  : ByteView(arrival->payload)));
  }
}

std::size_t Session::drain(std::chrono::milliseconds wall) {
  std::size_t dropped = 0;
  const Deadline deadline = Clock::now() + wall;
  device_clock_.stop_judging();  // what is dropped after a failed case belongs to a judged stream
  while (receive(deadline)) ++dropped;
  return dropped;
}

BytePattern Session::pattern(ByteView payload, const std::vector<std::size_t>& device_positions) const {
  BytePattern exact = BytePattern::exactly(payload);
  if (emulator_target()) return exact;
  return exact.keep_only(device_positions).with_length_rule(LengthRule::at_least);
}

BytePattern Session::pattern(const Response& response, const std::vector<std::size_t>& device_positions) const {
  return pattern(reply_bytes(response), device_positions);
}

BytePattern Session::pattern(const ReplyVector& vector) const {
  return emulator_target() ? vector.emulator_pattern() : vector.device_pattern();
}

const ReplyVector& Session::reply_vector(std::string_view name) const {
  const ReplyVector* vector = vectors_.reply(name);
  if (vector == nullptr) throw CaseFailed("spec 7.2 vector `" + std::string(name) + "` is missing from the vector table");
  return *vector;
}

Bytes Session::request_vector(std::string_view name) const {
  const RequestVector* vector = vectors_.request(name);
  if (vector == nullptr) throw CaseFailed("spec 7.1 vector `" + std::string(name) + "` is missing from the vector table");
  return vector->payload;
}

std::chrono::milliseconds Session::wall_for(SimMilliseconds simulated) const {
  if (options_.virtual_time) return std::chrono::milliseconds(0);
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(simulated.count() / options_.time_scale)));
}

std::chrono::milliseconds Session::reply_wait_after(SimMilliseconds simulated) const {
  return wall_for(simulated) + options_.reply_timeout;
}

void Session::sleep_simulated(SimMilliseconds simulated) const { std::this_thread::sleep_for(wall_for(simulated)); }

void Session::set_sector_table(const std::vector<SetFunction>& sectors) {
  for (const SetFunction& sector : sectors) {
    const Bytes expected = reply_bytes(SetFunctionReply{sector.sector});  // D3: echo of SECTORNUM
    Arrival reply = expect("SET_FUNCTION s" + std::to_string(sector.sector), encode_request(sector),
                           pattern(expected, {0, 1}));
    if (reply.payload.size() >= 4 && read_word_be(reply.payload, 2) == kSetFunctionInvalid) {
      throw CaseFailed("SET_FUNCTION s" + std::to_string(sector.sector) + ": refused with FF FF");
    }
  }
}

void Session::set_global(std::uint16_t sensor_id, std::uint16_t speed_hz, std::uint16_t step_ticks) {
  const Bytes request = encode_request(SetConfig{GlobalConfig{sensor_id, speed_hz, step_ticks, false}});
  expect("SET_CONFIG global " + std::to_string(sensor_id) + "/" + std::to_string(speed_hz) + " Hz/" +
             std::to_string(step_ticks) + " ticks",
         request, BytePattern::exactly(reply_bytes(SetConfigReply{kSetConfigSuccess})));
}

void Session::restore_baseline() {
  // A stream a failed case left running ends with this DO_RESET; the case was judged already.
  device_clock_.stop_judging();
  // DO_RESET level 2 halts the application and enters IDLE from any state (spec 3.3) and ends a
  // profile stream first (D10).
  expect("baseline DO_RESET 2", encode_request(DoReset{reset_level::kHaltToIdle}),
         BytePattern::exactly(reply_bytes(DoResetReply{reset_level::kHaltToIdle})),
         reply_wait_after(SimMilliseconds(10000)));
  set_sector_table({SetFunction{0, sector_function::kNormalMeasurement, 2160, 0},
                    SetFunction{1, sector_function::kNoMeasurement, 3600, 0}, SetFunction{2, 0, 0, 0},
                    SetFunction{3, 0, 0, 0}, SetFunction{4, 0, 0, 0}, SetFunction{5, 0, 0, 0},
                    SetFunction{6, 0, 0, 0}, SetFunction{7, 0, 0, 0}});
  // SET_CONFIG global last: it commits the sector table to flash as S1 observed (spec 3.3).
  set_global(kBaselineSensorId, kBaselineSpeedHz, kBaselineStepTicks);
}

void Session::enter_rotate(std::uint16_t frequency_hz) {
  // D7 / spec 6: the reply comes once the head is at speed; S2 allows 10 s.
  expect("TRANS_ROTATE " + std::to_string(frequency_hz), encode_request(TransRotate{frequency_hz}),
         pattern(TransRotateReply{status(SensorMode::rotate)}, {0, 1, 5}), reply_wait_after(SimMilliseconds(10000)));
}

void Session::enter_measure() {
  // Laser on with the next revolution (spec 6): allow a couple of revolutions of 5 Hz.
  expect("TRANS_MEASURE", encode_request(TransMeasure{}),
         pattern(TransMeasureReply{status(SensorMode::measure), measure_return::kOk}, {0, 1, 5, 6, 7}),
         reply_wait_after(SimMilliseconds(1000)));
}

std::uint16_t Session::read_clock_ms() {
  Arrival reply = expect("GET_SYNC_CLOCK", encode_request(GetSyncClock{}),
                         BytePattern::exactly(reply_bytes(SyncClockReply{0})).with_hole(2, 2));
  return read_word_be(reply.payload, 2);
}

void Session::close_transport() { transport_->close(); }

void Session::reopen_transport() {
  auto reopened = open_suite_transport(options_);
  if (!reopened) throw CaseFailed("reopen: " + reopened.error());
  transport_ = std::move(*reopened);
  dropped_at_stream_start_ = 0;  // a new transport counts from 0
  missing_in_stream_ = 0;
}

}  // namespace ldoem::conformance
