// One telegram transport to the scanner (design.md convention 2): send one payload, receive one
// payload before a deadline, close. Implemented for TCP (spec 4.1), serial (spec 4.2) and
// ISO-TP over CAN (D1); the Scanner, the hub and ldoem-scan see only this interface.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ldoem/driver/endpoint.hpp"
#include "ldoem/driver/error.hpp"
#include "ldoem/protocol/bytes.hpp"

namespace ldoem::driver {

using protocol::ByteView;
using protocol::Bytes;

// The driver is the real-world edge: deadlines are points on the monotonic clock
// (std::chrono::steady_clock is CLOCK_MONOTONIC on Linux).
using Clock = std::chrono::steady_clock;
using Deadline = Clock::time_point;

// What a transport saw but did not hand up; for diagnostics, never for control flow.
struct TransportCounters {
  std::uint64_t telegrams_sent = 0;
  std::uint64_t telegrams_received = 0;
  std::uint64_t dropped_frames = 0;  // bad checksum / CRC / hex / ISO-TP sequence, silently dropped
  std::uint64_t skipped_bytes = 0;   // bytes outside any frame
};

class TelegramTransport {
 public:
  virtual ~TelegramTransport() = default;

  // Sends one whole telegram payload (service WORD then parameters) in one piece (D10).
  // Errors: timeout (retryable) when the line would not take it before `deadline`,
  // connection_closed, system; on ISO-TP also timeout/refused when the peer's flow control
  // does not come or says overflow (D1).
  virtual Status send(ByteView payload, Deadline deadline) = 0;

  // The next whole telegram payload that arrived, in arrival order. Frames with a bad checksum
  // or CRC are dropped and counted, never returned. Errors: timeout (retryable) at
  // `deadline`, connection_closed, system.
  virtual Expected<Bytes, DriverError> receive(Deadline deadline) = 0;

  // The whole telegrams that have already arrived, without waiting (at most `limit`); the
  // Scanner reads them before it sends a request, since none of them can answer it (a
  // duplicated reply, one that came after its request timed out: D11). Default: none (a
  // transport that cannot look without waiting).
  virtual std::vector<Bytes> take_arrived(std::size_t limit);

  // Releases the descriptor; later calls answer connection_closed. Idempotent.
  virtual void close() = 0;

  // The endpoint text, used as the `object` of errors.
  virtual const std::string& name() const = 0;
  virtual TransportCounters counters() const = 0;
};

// TelegramTransport::take_arrived for a transport whose receive() with a passed deadline does not wait.
std::vector<Bytes> take_arrived_now(TelegramTransport& transport, std::size_t limit);

// Opens the transport an endpoint names. An `lpt:` endpoint is invalid_argument here (see
// open_lpt_port). TCP connects with a 1 s timeout (spec 6).
Expected<std::unique_ptr<TelegramTransport>, DriverError> open_transport(const Endpoint& endpoint);

}  // namespace ldoem::driver
