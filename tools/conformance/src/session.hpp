// What a conformance case works with: one open TelegramTransport to the endpoint, the options, the
// golden vectors, and steps that either return what arrived or end the case with a CaseFailed
// (the first failing step ends a case, like a GoogleTest ASSERT; nothing throws past the runner).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "byte_pattern.hpp"
#include "device_clock.hpp"
#include "ldoem/driver/transport.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/status.hpp"
#include "options.hpp"
#include "vector_table.hpp"

namespace ldoem::conformance {

using driver::Clock;
using driver::Deadline;
using SimMilliseconds = std::chrono::milliseconds;  // on the endpoint's simulated clock (D7)

// Ends the current case. `detail` holds indented lines (a hex diff) printed under the FAIL line.
class CaseFailed : public std::runtime_error {
 public:
  CaseFailed(std::string why, std::string detail = {}) : std::runtime_error(why), detail_(std::move(detail)) {}
  const std::string& detail() const { return detail_; }

 private:
  std::string detail_;
};

// A failure of the host link's promise rather than the device's: a quantity measured on the
// wall clock fell outside its tolerance. Where the runner probed the machine during the case
// (timing_probe.hpp) and saw it lose that much time itself, the case is INCONCLUSIVE instead.
class WallClockFailed : public CaseFailed {
 public:
  WallClockFailed(std::string why, double tolerance_ms, std::string detail = {})
      : CaseFailed(std::move(why), std::move(detail)), tolerance_ms_(tolerance_ms) {}
  double tolerance_ms() const { return tolerance_ms_; }

 private:
  double tolerance_ms_;
};

// A received telegram with its wall-clock arrival time.
struct Arrival {
  Bytes payload;
  Clock::time_point at;
};

class Session {
 public:
  Session(std::unique_ptr<driver::TelegramTransport> transport, const SuiteOptions& options, const VectorTable& vectors);

  const SuiteOptions& options() const { return options_; }
  const VectorTable& vectors() const { return vectors_; }
  const driver::Endpoint& endpoint() const { return *options_.endpoint; }
  bool emulator_target() const { return options_.target == Target::emulator; }

  // ---------------------------------------------------------------- telegram steps
  void send(ByteView payload);
  // The next telegram, or nullopt at the deadline.
  std::optional<Arrival> receive(Deadline deadline);
  // Sends `payload` and returns the first telegram that is not a profile (0x8301): S1 skips
  // profiles while it waits for a reply (spec 3.5). Fails after `wait` (reply_timeout by default).
  Arrival request(ByteView payload, std::optional<std::chrono::milliseconds> wait = std::nullopt);
  // request() then compare; `what` names the step in the FAIL line.
  Arrival expect(std::string_view what, ByteView payload, const BytePattern& reply,
                 std::optional<std::chrono::milliseconds> wait = std::nullopt);
  void check(std::string_view what, const BytePattern& expected, ByteView received);
  // The next telegram must be a profile; fails on a timeout or any other telegram.
  Arrival await_profile(std::string_view what, std::chrono::milliseconds wait);
  // Nothing at all may arrive for `wall`.
  void expect_silence(std::string_view what, std::chrono::milliseconds wall);
  // Reads and drops whatever arrives within `wall` (after a case, before the baseline).
  std::size_t drain(std::chrono::milliseconds wall);

  // The pattern a case asserts: every byte for the emulator; for the device only
  // `device_positions` (default: the service code) and at least that length.
  BytePattern pattern(ByteView payload, const std::vector<std::size_t>& device_positions = {0, 1}) const;
  BytePattern pattern(const protocol::Response& response, const std::vector<std::size_t>& device_positions = {0, 1}) const;
  BytePattern pattern(const ReplyVector& vector) const;
  const ReplyVector& reply_vector(std::string_view name) const;
  Bytes request_vector(std::string_view name) const;

  // ---------------------------------------------------------------- time (D7)
  // Wall time the endpoint needs for `simulated` (rounded up); zero in virtual time.
  std::chrono::milliseconds wall_for(SimMilliseconds simulated) const;
  // Wait for a reply that comes after `simulated` time on the device (e.g. spin-up).
  std::chrono::milliseconds reply_wait_after(SimMilliseconds simulated) const;
  void sleep_simulated(SimMilliseconds simulated) const;

  // ---------------------------------------------------------------- device state
  // IDLE, global config (1, 10 Hz, 4 ticks) and the D4 sector table, set explicitly so that
  // every case starts from the same place whatever ran before.
  void restore_baseline();
  void set_sector_table(const std::vector<protocol::SetFunction>& sectors);
  void set_global(std::uint16_t sensor_id, std::uint16_t speed_hz, std::uint16_t step_ticks);
  void enter_rotate(std::uint16_t frequency_hz = 0);
  void enter_measure();
  std::uint16_t read_clock_ms();

  // The transport itself, for cases that close and reopen it around a raw session.
  void close_transport();
  void reopen_transport();

  std::uint64_t profiles_skipped() const { return profiles_skipped_; }
  // Every profile that arrives, whichever step receives it, is judged on the device's own clock
  // (device_clock.hpp); a GET_PROFILE sent starts a new stream.
  const DeviceClockCheck& device_clock() const { return device_clock_; }
  driver::TransportCounters transport_counters() const { return transport_->counters(); }

  // On a serial line, `received` without the one 0x00 pad byte an odd payload of
  // `expected_size` bytes gets (spec 4.2: WORDs only); otherwise `received` unchanged.
  ByteView without_serial_pad(ByteView received, std::size_t expected_size) const;

 private:
  void log(const char* direction, ByteView payload) const;
  // Follows the head speed from the requests sent and the replies that confirm them.
  void note_request(ByteView payload);
  void note_reply(ByteView payload);

  std::unique_ptr<driver::TelegramTransport> transport_;
  const SuiteOptions& options_;
  const VectorTable& vectors_;
  std::uint64_t profiles_skipped_ = 0;
  DeviceClockCheck device_clock_;
  std::uint64_t dropped_at_stream_start_ = 0;  // the transport's dropped_frames at GET_PROFILE
  std::uint64_t missing_in_stream_ = 0;        // PROFILESENT gaps already put down to those drops
  std::uint16_t configured_hz_ = 10;  // D4
  std::optional<std::uint16_t> pending_config_hz_;  // SET_CONFIG global sent, reply not yet seen
  std::optional<std::uint16_t> pending_rotate_hz_;  // TRANS_ROTATE sent (0 = configured speed)
};

// Replies built from the typed protocol (encode_response), for readability in the cases.
Bytes reply_bytes(const protocol::Response& response);
protocol::StatusBlock status(protocol::SensorMode sensor, protocol::MotorMode motor = protocol::MotorMode::ok);
Bytes service_failure(std::uint16_t request_code, protocol::FailureReason reason);
constexpr std::uint16_t key_word(protocol::ConfigKey key) { return static_cast<std::uint16_t>(key); }

}  // namespace ldoem::conformance
