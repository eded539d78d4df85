// What a device instance in the daemon drives (daemon/device_instance.hpp): events in, Actions
// out (ports.hpp). The control unit is one model (an emulated LD-OEM); a recorded device built
// from a capture is another (emulator/device/replay, `ldoem-emud --replay`). Both sit behind the
// same endpoints, scheduler, wire tap and recording, so there is one copy of the host plumbing.
#pragma once

#include "ldoem/control/ports.hpp"
#include "ldoem/protocol/config.hpp"
#include "ldoem/protocol/framing.hpp"

namespace ldoem::control {

// Counters for the daemon's diagnostics; not device state (a reset keeps them).
struct Diagnostics {
  std::uint64_t skipped_profiles = 0;  // D10: revolutions skipped because the transport was busy
  std::uint64_t profiles_sent = 0;
  std::uint64_t service_failures_sent = 0;
  std::uint64_t spontaneous_resets = 0;  // D11 reset_spontaneous
  std::uint64_t power_cycles = 0;        // D11 power_cycle
  bool operator==(const Diagnostics&) const = default;
};

class DeviceModel {
 public:
  virtual ~DeviceModel() = default;

  // One request payload (service WORD first, framing removed) from a host connection.
  virtual Actions handle_request(SimTime now, ConnectionId from, protocol::ByteView payload,
                                 const TransportQuery& transport) = 0;
  // A timer from an earlier Actions. `transport` answers D10's busy question.
  virtual Actions on_timer(SimTime now, TimerId timer, const TransportQuery& transport) = 0;
  // D2: a frame the deframer dropped.
  virtual Actions on_framing_error(SimTime now, ConnectionId from, const protocol::FramingError& error) = 0;
  virtual Actions on_connection_closed(SimTime now, ConnectionId connection) = 0;

  // The CAN configuration in RAM (D1): the CAN endpoint's first pair at power-up.
  virtual const protocol::CanConfig& can_config() const = 0;
  virtual const Diagnostics& diagnostics() const = 0;
  // The daemon stops: a model may report what it counted.
  virtual void report_at_exit() const {}
};

}  // namespace ldoem::control
