// The D11 wire faults that act below the telegram, inside an endpoint: a corrupted checksum, bytes
// inserted between telegrams, a stalled or slow TCP connection, broken ISO-TP frames and flow
// control, and lost tilt steps on the LPT. (Whole-telegram faults, drop/delay/duplicate/truncate,
// act above the framing, in the WireTap.)
//
// An endpoint asks its hook at a few fixed points (framing a telegram, reading or writing a TCP
// connection, a host's ISO-TP first frame, an LPT clock edge) and applies the answer with its own
// framing. Without faults in the scene the daemon sets no hook: each point costs one null-pointer
// test, and the bytes are those of a daemon without the fault machinery (D9's rule, D11).
//
// The implementation (emulator/faults/injection, endpoint_faults.hpp) reads the fault scheduler;
// answers are deterministic for a given scene, seed and conversation. A hook never calls back into
// the endpoint.
#pragma once

#include <cstdint>
#include <optional>

#include "ldoem/control/ports.hpp"
#include "ldoem/protocol/bytes.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::endpoints {

// What happens to the first consecutive frame of an ISO-TP message we send (D11 isotp_drop_cf,
// isotp_repeat_cf, isotp_bad_sn).
enum class ConsecutiveFrameFault : std::uint8_t { none, drop, repeat, bad_sequence };

// What happens to one telegram on its way out (TCP, serial, CAN).
struct TelegramFaults {
  bool corrupt_checksum = false;      // TCP: the XOR byte inverted; serial: the first package's CRC inverted
  protocol::Bytes garbage_before;     // written between the previous telegram and this one
  ConsecutiveFrameFault first_consecutive_frame = ConsecutiveFrameFault::none;  // CAN only

  bool any() const {
    return corrupt_checksum || !garbage_before.empty() || first_consecutive_frame != ConsecutiveFrameFault::none;
  }
};

// How a host's ISO-TP first frame is answered (D11 isotp_fc_overflow, isotp_fc_wait).
enum class FirstFrameFault : std::uint8_t { none, overflow, wait };

class WireFaultHook {
 public:
  virtual ~WireFaultHook() = default;

  // A telegram (payload: service WORD first) is about to be framed for `to`.
  virtual TelegramFaults on_outgoing_telegram(control::ConnectionId to, protocol::ByteView payload,
                                              base::SimTime now) = 0;

  // TCP: the connection neither reads nor writes before the returned time (tcp_stall). The time
  // may be a re-check point: asked again then, the hook answers again.
  virtual std::optional<base::SimTime> stalled_until(control::ConnectionId connection, base::SimTime now) = 0;
  // TCP: the connection's bytes leave at this many bytes per second (bandwidth).
  virtual std::optional<std::uint32_t> bytes_per_second(control::ConnectionId connection, base::SimTime now) = 0;

  // CAN: a host's first frame of a request of `service` (the request code, the first two payload
  // bytes the first frame carries) arrived on `from`'s identifier pair.
  virtual FirstFrameFault on_host_first_frame(control::ConnectionId from, std::uint16_t service, base::SimTime now) = 0;
  // CAN: a first frame held by isotp_fc_wait is still held (another FC WAIT is due).
  virtual bool keeps_host_waiting(control::ConnectionId from, base::SimTime now) = 0;

  // LPT: a rising clock edge, one step; true when the plate does not follow it (lpt_lose_steps, lpt_jam).
  virtual bool loses_step(base::SimTime at) = 0;
};

}  // namespace ldoem::endpoints
