// The LD-OEM API over any TelegramTransport: one method per service of spec 3.2 with a published
// layout, reply matching as the public Ethernet driver does it (spec 3.5, section 2.2), the
// D2 SERVICE_FAILURE mapped to a typed error, and the lifecycle of lifecycle.hpp.
//
// Reply matching: after sending request R the Scanner reads telegrams until the one whose code
// is R | 0x8000. On the way, profile telegrams (0x8301) are queued for next_profile() and never
// lost; SERVICE_FAILURE naming R ends the wait with ErrorKind::service_failure; anything else
// is counted in counters().skipped_telegrams and skipped. Telegrams that arrived before R was
// sent (TelegramTransport::take_arrived) cannot answer it and are skipped the same way (counted in
// stale_replies): a duplicated reply or one later than its timeout is not taken for R's. One attempt, no hidden retries: a
// timeout is returned to the caller (spec 6: S1 waits 5 s once).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ldoem/driver/error.hpp"
#include "ldoem/driver/lifecycle.hpp"
#include "ldoem/driver/transport.hpp"
#include "ldoem/protocol/config.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/status.hpp"

namespace ldoem::driver {

// Spec 6: 5 s per request (S1, S2); TRANS_ROTATE gets 10 s for the spin-up (S2).
inline constexpr std::chrono::milliseconds kDefaultRequestTimeout{5000};
inline constexpr std::chrono::milliseconds kDefaultRotateTimeout{10000};

using TransportOpener = std::function<Expected<std::unique_ptr<TelegramTransport>, DriverError>()>;

// How reconnect() tries: `attempts` openings plus GET_STATUS; the first pause is `interval`,
// each next one `backoff` times the last, at most `max_interval`. The default (10 attempts,
// 500 ms apart, no backoff) rides out a power cycle of up to about 5 s (D11 power_cycle's off_s;
// the LD-OEM boots in that time) and then gives up: bounded, never a loop. A device that takes
// longer to come back (a bench supply, a switch) wants more attempts or a backoff.
struct ReconnectPolicy {
  std::uint32_t attempts = 10;
  std::chrono::milliseconds interval{500};
  double backoff = 1.0;                         // >= 1; 2 doubles every pause
  std::chrono::milliseconds max_interval{30000};
  bool operator==(const ReconnectPolicy&) const = default;
};

// The pause before attempt `attempt` (2, 3, ...): interval * backoff^(attempt - 2), capped at
// max_interval (a backoff below 1 counts as 1).
std::chrono::milliseconds reconnect_pause(const ReconnectPolicy& policy, std::uint32_t attempt);

struct ScannerOptions {
  std::chrono::milliseconds request_timeout = kDefaultRequestTimeout;
  std::chrono::milliseconds rotate_timeout = kDefaultRotateTimeout;
  // The format set_state(LifecycleState::active) streams with (S1's range format).
  std::uint16_t stream_format = protocol::kFormatRange;
  // Opens the transport again for reconnect(); empty: reconnect() is unsupported.
  TransportOpener reopen;
  ReconnectPolicy reconnect;
  // How reconnect() waits between attempts. Empty: std::this_thread::sleep_for.
  std::function<void(std::chrono::milliseconds)> sleep;
  // Where "now" comes from when a timeout becomes a deadline. Empty: Clock::now. Tests inject
  // a fixed clock to check the exact deadlines handed to the transport.
  std::function<Deadline()> clock;
};

struct IdentificationEntry {
  std::uint16_t item = 0;
  std::string text;
  bool operator==(const IdentificationEntry&) const = default;
};

// S1's order of the 11 items (spec 3.3, 7.3 step 2).
inline constexpr std::array<std::uint16_t, 11> kIdentificationItems{
    0x0000, 0x0001, 0x0002, 0x0003, 0x0004, 0x0010, 0x0011, 0x0012, 0x0020, 0x0021, 0x0022};

// One entry of the sector table as written (spec 3.6): sector i is the i-th entry.
struct SectorDefinition {
  std::uint16_t function = protocol::sector_function::kNotInitialised;
  std::uint16_t stop_ticks = 0;
  bool operator==(const SectorDefinition&) const = default;
};

struct ScannerCounters {
  std::uint64_t requests_sent = 0;
  std::uint64_t replies_matched = 0;
  std::uint64_t skipped_telegrams = 0;  // neither our reply, nor a profile, nor our failure
  std::uint64_t profiles_queued = 0;    // profiles that arrived while a reply was awaited
  std::uint64_t profiles_delivered = 0;
  std::uint64_t profiles_skipped = 0;   // 0x8301 with another format than the stream's
  std::uint64_t reconnects = 0;         // successful reconnect() calls
  std::uint64_t stale_replies = 0;      // replies already there before a request: skipped
};

class Scanner {
 public:
  explicit Scanner(std::unique_ptr<TelegramTransport> transport, ScannerOptions options = {});
  ~Scanner();
  Scanner(const Scanner&) = delete;
  Scanner& operator=(const Scanner&) = delete;

  // ---------------------------------------------------------------------------- lifecycle
  LifecycleState state() const { return state_; }
  // Executes plan_transition(state(), target). wrong_state for refused pairs.
  Status set_state(LifecycleState target);
  // Unconfigured -> Connected through GET_STATUS, returning it; in Connected/Active a plain
  // get_status(). wrong_state when Closed.
  Expected<protocol::GetStatusReply, DriverError> connect();
  // Closes the transport (without CANCEL_PROFILE; set_state(closed) sends one when Active).
  void close();
  // After a connection_closed (a TCP reset, a power cycle) or any error the caller wants to
  // start afresh from: closes the transport, forgets queued profiles and the stream, and tries
  // options().reconnect.attempts times, interval apart, to open the transport again
  // (options().reopen) and get a GET_STATUS answered. Success: Connected, the status returned
  // (after a power cycle the D4 power-up state: IDLE, RAM configuration lost). Failure: the
  // last attempt's error, with the attempt count in its detail; the handle stays Closed.
  // unsupported when options().reopen is empty. The one way out of Closed.
  Expected<protocol::GetStatusReply, DriverError> reconnect();

  // ------------------------------------------------------------------- status group 0x01
  Expected<protocol::GetStatusReply, DriverError> get_status();
  Expected<std::string, DriverError> get_identification(std::uint16_t item);
  Expected<std::vector<IdentificationEntry>, DriverError> identify_all();
  Expected<std::uint16_t, DriverError> get_signal();
  // refused when the reply's byte 2 is not 0 (S1's check, spec 3.3).
  Status set_signal(std::uint16_t port_value);

  // ------------------------------------------------------------- configuration group 0x02
  // unexpected_reply when the echoed key differs from the one asked for.
  Expected<protocol::ConfigBody, DriverError> get_config(protocol::ConfigKey key);
  Expected<protocol::GlobalConfig, DriverError> get_global_config();
  Expected<protocol::EthernetConfig, DriverError> get_ethernet_config();
  Expected<protocol::SerialConfig, DriverError> get_serial_config();
  Expected<protocol::CanConfig, DriverError> get_can_config();
  Expected<protocol::InterlaceConfig, DriverError> get_interlace_config();
  // refused with in_band_code = the result WORD when it is not 0 (spec 3.3, D2).
  Status set_config(const protocol::ConfigBody& body);

  // Clock services: each returns the device clock after the call, in ms (spec 3.3).
  Expected<std::uint16_t, DriverError> set_time_abs(std::uint16_t time_ms);
  Expected<std::uint16_t, DriverError> set_time_rel(std::int16_t delta_ms);
  Expected<std::uint16_t, DriverError> get_sync_clock();

  // Near-field suppression on/off; unexpected_reply when the echo is not item 1.
  Status set_filter(bool near_field_suppression);

  // unexpected_reply when the echoed sector differs.
  Expected<protocol::GetFunctionReply, DriverError> get_function(std::uint16_t sector);
  // refused (in_band_code 0xFFFF) when the device answers `FF FF`.
  Status set_function(const protocol::SetFunction& sector);
  // S1's way: GET_FUNCTION 0, 1, ... up to and including the first not-initialised sector or
  // sector 7.
  Expected<std::vector<protocol::GetFunctionReply>, DriverError> read_sector_table();
  // SET_FUNCTION for each definition (sector = index), then, if fewer than 8, one
  // not-initialised sector with stop 0 that ends the table (S1's layout, spec 3.6).
  // invalid_argument for more than 8 definitions.
  Status write_sector_table(std::span<const SectorDefinition> sectors, bool to_flash);

  // ------------------------------------------------------------------- working group 0x04
  // Each returns the status block after the transition. In Active, a successful TRANS_* or
  // DO_RESET ends the stream (D10): the state becomes Connected. A TRANS_ROTATE or
  // TRANS_MEASURE reply whose status reports a fault (motor nibble, sensor ERROR: D11) is the
  // error device_fault carrying the status byte.
  Expected<protocol::StatusBlock, DriverError> trans_idle();
  // `frequency_hz` 0 = the configured speed (spec 3.3); `timeout` default: options'
  // rotate_timeout (10 s, spin-up, spec 6).
  Expected<protocol::StatusBlock, DriverError> trans_rotate(
      std::uint16_t frequency_hz = 0, std::optional<std::chrono::milliseconds> timeout = std::nullopt);
  // refused with in_band_code = RETURNCODE 1..4 (spec 3.3).
  Expected<protocol::StatusBlock, DriverError> trans_measure();
  // unexpected_reply when the echoed level differs.
  Status do_reset(std::uint16_t level);

  // --------------------------------------------------------------- measurement group 0x03
  // Sends GET_PROFILE (count 0 = stream until cancel) and moves to Active; no reply is
  // awaited: the profiles are the answer (spec 3.5). A SERVICE_FAILURE for it surfaces from
  // next_profile().
  Status get_profile(std::uint16_t count, std::uint16_t format);
  // The next profile of the stream, queued ones first. Errors: timeout at `deadline`,
  // service_failure (the device refused GET_PROFILE: state back to Connected),
  // corrupted_reply (a profile that does not decode: cut short on the way; the stream goes on),
  // wrong_state (no stream and no queue).
  // After the count-th profile of a finite request the state returns to Connected.
  Expected<protocol::Profile, DriverError> next_profile(Deadline deadline);
  // Stops the stream; returns the status block. State back to Connected.
  Expected<protocol::StatusBlock, DriverError> cancel_profile();

  std::size_t queued_profiles() const { return profiles_.size(); }
  ScannerCounters counters() const { return counters_; }
  TelegramTransport& transport() { return *transport_; }
  const ScannerOptions& options() const { return options_; }

 private:
  Deadline now() const;
  Status require_talking(std::uint16_t request_code) const;
  DriverError annotate(DriverError error, std::uint16_t request_code) const;
  DriverError error_for(ErrorKind kind, std::uint16_t request_code, std::string detail = {}) const;
  Status send_request(const protocol::Request& request, Deadline deadline);
  Expected<Bytes, DriverError> exchange(const protocol::Request& request, std::chrono::milliseconds timeout,
                                        bool allow_unconfigured = false);
  Expected<Bytes, DriverError> await_reply(std::uint16_t request_code, Deadline deadline,
                                           std::chrono::milliseconds timeout);
  template <class Reply>
  Expected<Reply, DriverError> call(const protocol::Request& request, std::chrono::milliseconds timeout,
                                    bool allow_unconfigured = false);
  template <class Body>
  Expected<Body, DriverError> get_config_as();
  Expected<protocol::Profile, DriverError> deliver_profile(const Bytes& payload);
  Status check_device_status(const protocol::StatusBlock& status, std::uint16_t request_code) const;
  void sleep_for(std::chrono::milliseconds pause) const;
  void take_stale_telegrams();
  void end_stream();

  std::unique_ptr<TelegramTransport> transport_;
  ScannerOptions options_;
  LifecycleState state_ = LifecycleState::unconfigured;
  std::deque<Bytes> profiles_;
  std::optional<protocol::ServiceFailure> stream_failure_;
  std::uint16_t stream_format_ = protocol::kFormatRange;
  std::uint32_t stream_profiles_left_ = 0;  // 0: unlimited stream
  ScannerCounters counters_;
};

}  // namespace ldoem::driver
