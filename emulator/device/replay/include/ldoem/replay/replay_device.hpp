// A recorded LD-OEM (docs/replay.md): the device of a capture, answering a live host with what
// the real one answered. Pure: requests and simulated time go in, telegrams to send and when to
// send them come out; ldoem-replay puts it behind the emulator's endpoints.
//
// The recording is cut into exchanges (capture::exchanges_of). A request is matched
//   1. to the next exchange in recorded order when its payload is byte-identical, else
//   2. to the first later exchange with an identical request, else
//   3. to any earlier one (a host that repeats itself), oldest first;
// and answered with that exchange's telegrams at their recorded delays (scaled). A request that
// matches nothing gets a diagnostic and the D2 failure reply: the reason decode_request gives
// for a telegram that is not a valid request, else reason 3 (the recorded device was never asked
// this, so it cannot be done "now").
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/capture/capture_conversation.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::replay {

using protocol::Bytes;
using base::SimTime;

using capture::Exchange;
using capture::RecordedAnswer;

struct ScheduledTelegram {
  SimTime at{};
  Bytes payload;
  bool operator==(const ScheduledTelegram&) const = default;
};

struct ReplayAnswer {
  std::vector<ScheduledTelegram> telegrams;  // in sending order, `at` never decreasing
  std::optional<std::string> diagnostic;     // why the request was not matched
  std::optional<std::size_t> exchange;       // which exchange answered
};

struct ReplayCounters {
  std::uint64_t requests = 0;
  std::uint64_t in_order = 0;    // matched the next exchange
  std::uint64_t out_of_order = 0;
  std::uint64_t unexpected = 0;  // answered with a failure reply
};

class ReplayDevice {
 public:
  // speed: recorded seconds per replayed second (2 plays the delays twice as fast).
  explicit ReplayDevice(std::vector<Exchange> exchanges, double speed = 1.0);

  // A request from the host at `now`.
  [[nodiscard]] ReplayAnswer on_request(SimTime now, protocol::ByteView request);
  const ReplayCounters& counters() const { return counters_; }
  std::size_t exchange_count() const { return exchanges_.size(); }
  // Exchanges never asked for so far (a conformance view of how much of the recording ran).
  std::size_t unused_exchanges() const;

 private:
  std::optional<std::size_t> match(protocol::ByteView request) const;

  std::vector<Exchange> exchanges_;
  std::vector<bool> used_;
  std::size_t next_ = 0;
  double speed_;
  ReplayCounters counters_;
};

}  // namespace ldoem::replay
