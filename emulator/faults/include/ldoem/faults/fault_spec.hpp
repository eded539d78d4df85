// One fault entry: what to inject (a D11 kind and its parameters), when (a trigger) and for how
// long (duration or count). The same grammar serves a scene's `faults:` list (YAML) and the
// control socket's inject-fault arguments (JSON): both readers hand each field to apply_field()
// and the whole entry to check_entry(), so the two syntaxes cannot drift apart.
//
// Fields (flattened keys; the YAML/JSON maps `on:` and `every:` give "on.service" etc.):
//   kind                  a D11 name (fault_kind.hpp)
//   at_s                  trigger: at this simulated time (seconds since the daemon started)
//   on.service, on.nth    trigger: on the nth request of the service (nth >= 1)
//   every.service, every.count   trigger: on every count-th request of the service
//   probability           trigger: each request (of `service` if given) starts the fault with
//                         this probability, drawn counter-based from the scene's seed
//   (no trigger)          now (control socket) or at time 0 (scene)
//   duration_s | count    how long it stays active; count = affected telegrams (wire faults) or
//                         lost steps (lpt_lose_steps). Neither: wire faults act once, device
//                         faults stay until cleared.
//   transport             wire faults: tcp, serial, can, lpt (default: every one the kind has)
//   service               wire faults: only replies to this service (default: the trigger's)
//   from_deg, to_deg      blind: the sector (may wrap through 0)
//   fraction              blind (share of beams), window_dirt (share of power lost), in [0, 1]
//   delay_s, bytes_kept, bytes, bytes_per_s, off_s   see FaultParam
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "ldoem/faults/fault_kind.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::faults {

using base::SimTime;

// Upper bounds of the values that size the daemon's memory or time (issue 27, docs/robustness.md).
// Every trigger time, duration_s and off_s: at most 1e6 s; every count: at most 1e12.
inline constexpr double kMaxFaultSeconds = 1.0e6;
// delay_reply: a reply later than this is lost to any host (the driver gives up after seconds).
inline constexpr double kMaxDelaySeconds = 60.0;
// garbage: a burst of line noise, built whole in memory for each telegram it precedes. 4096
// bytes keep it well inside a TCP connection's output queue (372 800 bytes) and the CAN
// backlog (4096 frames of 8 bytes); above about 372 800 it could never arrive at all.
inline constexpr std::uint32_t kMaxGarbageBytes = 4096;
// bandwidth: 1 Gbit/s, faster than any of the device's links.
inline constexpr std::uint32_t kMaxBytesPerSecond = 125'000'000;

struct TriggerNow {
  bool operator==(const TriggerNow&) const = default;
};
struct TriggerAt {
  SimTime at{};
  bool operator==(const TriggerAt&) const = default;
};
struct TriggerOnNth {
  std::uint16_t service = 0;
  std::uint64_t nth = 1;
  bool operator==(const TriggerOnNth&) const = default;
};
struct TriggerEvery {
  std::uint16_t service = 0;
  std::uint64_t count = 1;
  bool operator==(const TriggerEvery&) const = default;
};
struct TriggerProbability {
  double probability = 0.0;  // per matching request
  bool operator==(const TriggerProbability&) const = default;
};
using Trigger = std::variant<TriggerNow, TriggerAt, TriggerOnNth, TriggerEvery, TriggerProbability>;

struct FaultSpec {
  FaultKind kind = FaultKind::drop_reply;
  Trigger trigger;
  std::optional<SimTime> duration;
  std::optional<std::uint64_t> count;
  std::optional<Transport> transport;  // empty: every transport the kind applies to
  std::optional<std::uint16_t> service;  // request code whose replies are affected
  // blind: a sector in 1/16 deg ticks [from, to), wrapping through 0 when from > to.
  std::optional<std::uint16_t> from_ticks;
  std::optional<std::uint16_t> to_ticks;
  std::optional<double> fraction;
  SimTime delay{};                    // delay_reply
  std::uint32_t bytes_kept = 0;       // truncate_reply
  std::uint32_t garbage_bytes = 8;    // garbage
  std::uint32_t bytes_per_s = 1000;   // bandwidth
  SimTime off{std::chrono::seconds(1)};  // power_cycle
  bool operator==(const FaultSpec&) const = default;
};

enum class FieldErrorKind : std::uint8_t {
  unknown_key,      // a key the grammar (or this kind) does not define
  unknown_kind,     // not a D11 name
  unknown_service,  // not a request name of spec 3.2
  wrong_type,       // text where a number belongs, ...
  out_of_range,     // negative time, fraction over 1, nth 0, ...
  missing_key,      // no kind
  conflicting_keys, // two triggers, duration and count, a transport the kind has not
};

struct FieldError {
  FieldErrorKind kind = FieldErrorKind::wrong_type;
  std::string key;     // the flattened key at fault ("on.nth"); empty for the whole entry
  std::string detail;  // "must be in [0, 1]"
};

// A field's value as either syntax gives it: a number or a text.
using FieldValue = std::variant<double, std::string>;

// Reads one entry field by field. Keys may come in any order; kind-dependent checks run in
// finish(). The first error wins and is kept; later set() calls are ignored.
class FaultEntryBuilder {
 public:
  // "on" and "every" are maps in both syntaxes: readers pass their members as "on.service" etc.
  static bool is_trigger_map(std::string_view key) { return key == "on" || key == "every"; }

  [[nodiscard]] std::optional<FieldError> set(std::string_view key, const FieldValue& value);
  // The finished entry, or the problem with the entry as a whole (key empty) or one key.
  [[nodiscard]] std::variant<FaultSpec, FieldError> finish() const;

 private:
  std::optional<FieldError> set_trigger(std::string_view key, const FieldValue& value);
  FaultSpec spec_;
  bool has_kind_ = false;
  int triggers_ = 0;
  bool has_on_service_ = false, has_on_nth_ = false, has_every_service_ = false,
       has_every_count_ = false;
  bool has_duration_ = false, has_count_ = false;
  std::vector<std::pair<std::string, FaultParam>> params_;
};

// The spec as one line of text ("motor_stall at_s=2 duration_s=1"), for logs and events.
std::string describe(const FaultSpec& spec);

}  // namespace ldoem::faults
