// The seam through which every telegram in and out of a device, on every transport, can be
// observed and altered: recording a session (captures) and injecting wire faults plug in here
// without touching any endpoint. The device instance calls the tap once per telegram, after
// deframing (from the host) and before framing (to the host); framing errors are not telegrams
// and do not pass it.
//
// A tap may change `payload` (corrupt it), or return drop (the telegram is lost on the wire). To
// delay a telegram a tap drops it and hands it back later through the device instance's
// deliver_from_host / send_to_host, which do not pass the tap again; to reset a connection it
// calls the device instance's disconnect. The tap is called on the loop's thread and must not
// block.
#pragma once

#include <cstdint>

#include "ldoem/control/ports.hpp"
#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/wire_direction.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::endpoints {

struct WireTelegram {
  protocol::WireDirection direction = protocol::WireDirection::host_to_device;
  control::ConnectionId connection;
  base::SimTime at{};
  protocol::Bytes payload;  // service WORD first, no framing; the tap may alter it
  bool is_profile = false;  // device_to_host only: a 0x8301 profile of a running GET_PROFILE
};

enum class WireVerdict : std::uint8_t { pass, drop };

class WireTap {
 public:
  virtual ~WireTap() = default;
  virtual WireVerdict on_telegram(WireTelegram& telegram) = 0;
  // A host connection ended, in order with the telegrams around it: `reset` when the device
  // dropped it (DeviceInstance::disconnect: a tcp_reset fault, a power cycle), else an orderly
  // close (the host closed, a timeout). A recording writes FIN or RST (docs/capture.md).
  virtual void on_connection_closed(control::ConnectionId /*connection*/, base::SimTime /*at*/, bool /*reset*/) {}
};

}  // namespace ldoem::endpoints
