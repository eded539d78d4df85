#include "ldoem/capture/telegram_recorder.hpp"

#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace ldoem::capture {

Written TelegramRecorder::record(base::SimTime time, protocol::Transport transport, std::uint32_t connection,
                                     WireDirection direction, ByteView payload) {
  switch (transport) {
    case protocol::Transport::tcp:
      return writer_.write_tcp(time, connection, direction, protocol::encode_tcp_frame(payload));
    case protocol::Transport::serial:
      return writer_.write_serial(time, direction,
                                  direction == WireDirection::host_to_device ? protocol::encode_serial_request(payload)
                                                                             : protocol::encode_serial_reply(payload));
    case protocol::Transport::can:
      return record_isotp(time, direction, payload);
    case protocol::Transport::lpt:
      break;  // the stepper port carries no telegrams
  }
  return base::Unexpected(std::string("record: unknown transport"));
}

Written TelegramRecorder::connection_closed(base::SimTime time, protocol::Transport transport, std::uint32_t connection,
                                                bool reset) {
  if (transport != protocol::Transport::tcp) return std::monostate{};
  return writer_.close_tcp(time, connection, reset);
}

Written TelegramRecorder::record_isotp(base::SimTime time, WireDirection direction, ByteView payload) {
  if (payload.empty()) return std::monostate{};  // ISO-TP cannot carry an empty message (nothing was on the bus)
  const bool to_device = direction == WireDirection::host_to_device;
  const std::uint32_t data_id = to_device ? ids_.request_id : ids_.response_id;
  const std::uint32_t flow_control_id = to_device ? ids_.response_id : ids_.request_id;
  const WireDirection back = to_device ? WireDirection::device_to_host : WireDirection::host_to_device;
  protocol::IsoTpSender sender({.data_id = data_id});
  if (!sender.start(base::SimTime{}, payload)) return base::Unexpected(std::string("record: telegram too large for ISO-TP"));
  protocol::IsoTpReceiver receiver({.flow_control_id = flow_control_id, .max_message_bytes = payload.size()});
  // Bounded: one FC plus one CF per 7 bytes.
  for (std::size_t round = 0; round <= payload.size() / 7 + 2; ++round) {
    const protocol::IsoTpSendPoll poll = sender.poll(base::SimTime{});
    for (const auto& frame : poll.frames) {
      if (Written written = writer_.write_can(time, frame, direction); !written) return written;
      const auto result = receiver.on_frame(base::SimTime{}, frame);
      if (result.flow_control) {
        if (Written written = writer_.write_can(time, *result.flow_control, back); !written) return written;
        sender.on_flow_control(base::SimTime{}, *result.flow_control);
      }
      if (result.message) return std::monostate{};
    }
  }
  return base::Unexpected(std::string("record: ISO-TP segmentation did not finish"));
}

}  // namespace ldoem::capture
