// Records telegrams (payloads, as a device or a host sees them after deframing) into a capture
// file in the form each transport puts them on the wire (docs/capture.md):
//   TCP     the telegram framed (spec 4.1) on a synthesized connection;
//   serial  framed as a host request (spec 4.2) or as the device's reply packages;
//   CAN     segmented by ISO-TP (D1) on the request or response identifier, with the receiver's
//           flow control for a multi-frame telegram, all frames at the telegram's time.
// Used by `ldoem-emud --record` (through the endpoints' WireTap) and by
// `ldoem-conformance --record`. The bytes are re-framed from the payload, so a telegram the
// deframer accepted is recorded in canonical form (lowercase hex, unpadded CAN frames).
#pragma once

#include <cstdint>
#include <string>

#include "ldoem/capture/capture_writer.hpp"
#include "ldoem/capture/capture_conversation.hpp"
#include "ldoem/protocol/isotp.hpp"

namespace ldoem::capture {

struct RecorderCanIds {
  std::uint32_t request_id = protocol::kIsoTpHostToDeviceId;
  std::uint32_t response_id = protocol::kIsoTpDeviceToHostId;
};

class TelegramRecorder {
 public:
  TelegramRecorder(CaptureWriter& writer, RecorderCanIds ids = {}) : writer_(writer), ids_(ids) {}

  // The error when the telegram was not written.
  [[nodiscard]] Written record(base::SimTime time, protocol::Transport transport, std::uint32_t connection,
                                   WireDirection direction, ByteView payload);
  // TCP: FIN both ways, or RST from the device when `reset` (CaptureWriter::close_tcp); the
  // other transports have no connections to close.
  [[nodiscard]] Written connection_closed(base::SimTime time, protocol::Transport transport, std::uint32_t connection,
                                              bool reset = false);
  void set_can_ids(RecorderCanIds ids) { ids_ = ids; }

 private:
  Written record_isotp(base::SimTime time, WireDirection direction, ByteView payload);

  CaptureWriter& writer_;
  RecorderCanIds ids_;
};

}  // namespace ldoem::capture
