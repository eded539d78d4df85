#include "ldoem/endpoints/isotp_channel.hpp"

#include <algorithm>
#include <utility>

namespace ldoem::endpoints {
namespace {

protocol::IsoTpReceiverConfig receiver_config(const IsoTpChannelConfig& config) {
  protocol::IsoTpReceiverConfig receiver;
  receiver.flow_control_id = config.ids.response_id;
  receiver.block_size = config.block_size;
  receiver.st_min = config.st_min;
  receiver.pad_frames = config.pad_frames;
  return receiver;
}

protocol::IsoTpSenderConfig sender_config(const IsoTpChannelConfig& config) {
  protocol::IsoTpSenderConfig sender;
  sender.data_id = config.ids.response_id;
  sender.pad_frames = config.pad_frames;
  sender.max_wait_frames = config.max_wait_frames;
  return sender;
}

}  // namespace

IsoTpChannel::IsoTpChannel(IsoTpChannelConfig config)
    : config_(config), receiver_(receiver_config(config)), sender_(sender_config(config)) {}

IsoTpChannelOutput IsoTpChannel::on_frame(SimTime now, const protocol::CanFrame& frame) {
  IsoTpChannelOutput out;
  if (!accepts(frame)) {
    return out;
  }
  if (protocol::isotp_frame_type(frame) == protocol::IsoTpFrameType::flow_control) {
    // The host paces our sender (D1: honour the host's flow control).
    sender_.on_flow_control(now, frame);
  } else {
    note_receive(receiver_.on_frame(now, frame), out);
  }
  pump(now, out);
  return out;
}

IsoTpChannelOutput IsoTpChannel::send(SimTime now, protocol::ByteView telegram) {
  IsoTpChannelOutput out;
  if (queue_.size() >= config_.max_queued_telegrams) {
    ++counters_.queue_overflows;
  } else {
    queue_.push_back(Queued{protocol::Bytes(telegram.begin(), telegram.end()), {}, ConsecutiveFrameFault::none});
  }
  pump(now, out);
  return out;
}

IsoTpChannelOutput IsoTpChannel::send(SimTime now, protocol::ByteView telegram, TelegramFaults faults) {
  IsoTpChannelOutput out;
  if (queue_.size() >= config_.max_queued_telegrams) {
    ++counters_.queue_overflows;
  } else {
    queue_.push_back(Queued{protocol::Bytes(telegram.begin(), telegram.end()),
                            garbage_frames(config_.ids.response_id, faults.garbage_before),
                            faults.first_consecutive_frame});
  }
  pump(now, out);
  return out;
}

std::vector<protocol::CanFrame> garbage_frames(std::uint32_t id, protocol::ByteView bytes) {
  std::vector<protocol::CanFrame> frames;
  for (std::size_t offset = 0; offset < bytes.size(); offset += protocol::kCanMaxDataBytes) {
    protocol::CanFrame frame;
    frame.id = id;
    frame.length = static_cast<std::uint8_t>(std::min(protocol::kCanMaxDataBytes, bytes.size() - offset));
    std::copy_n(bytes.begin() + static_cast<std::ptrdiff_t>(offset), frame.length, frame.data.begin());
    frame.data[0] = static_cast<std::uint8_t>(0x20 | (frame.data[0] & 0x0F));
    frames.push_back(frame);
  }
  return frames;
}

// The sender's frames, with the running message's D11 consecutive-frame fault applied to its
// first consecutive frame.
void IsoTpChannel::put_out(const std::vector<protocol::CanFrame>& frames, IsoTpChannelOutput& out) {
  for (const protocol::CanFrame& frame : frames) {
    if (pending_frame_fault_ == ConsecutiveFrameFault::none ||
        protocol::isotp_frame_type(frame) != protocol::IsoTpFrameType::consecutive_frame) {
      out.frames.push_back(frame);
      continue;
    }
    const ConsecutiveFrameFault fault = std::exchange(pending_frame_fault_, ConsecutiveFrameFault::none);
    switch (fault) {
      case ConsecutiveFrameFault::drop:
        break;
      case ConsecutiveFrameFault::repeat:
        out.frames.push_back(frame);
        out.frames.push_back(frame);
        break;
      case ConsecutiveFrameFault::bad_sequence: {
        protocol::CanFrame wrong = frame;
        wrong.data[0] = static_cast<std::uint8_t>(0x20 | ((frame.data[0] + 1) & 0x0F));
        out.frames.push_back(wrong);
        break;
      }
      case ConsecutiveFrameFault::none:
        out.frames.push_back(frame);
        break;
    }
  }
}

IsoTpChannelOutput IsoTpChannel::poll(SimTime now) {
  IsoTpChannelOutput out;
  if (const auto due = receiver_.deadline(); due && *due <= now) {
    note_receive(receiver_.on_timer(now), out);
  }
  pump(now, out);
  return out;
}

std::optional<SimTime> IsoTpChannel::deadline() const {
  std::optional<SimTime> earliest = receiver_.deadline();
  if (const auto sending = sender_.deadline(); sending && (!earliest || *sending < *earliest)) {
    earliest = sending;
  }
  return earliest;
}

void IsoTpChannel::pump(SimTime now, IsoTpChannelOutput& out) {
  for (;;) {
    if (sender_.busy()) {
      auto polled = sender_.poll(now);
      put_out(polled.frames, out);
    }
    if (sender_.busy()) {
      return;  // waiting for flow control or STmin
    }
    if (!sender_counted_) {
      sender_counted_ = true;
      if (sender_.state() == protocol::IsoTpSender::State::failed) {
        ++counters_.send_failures;
      } else {
        ++counters_.telegrams_sent;
      }
    }
    if (queue_.empty()) {
      return;
    }
    Queued next = std::move(queue_.front());
    queue_.pop_front();
    if (auto started = sender_.start(now, next.telegram); !started) {
      ++counters_.send_failures;  // empty or over 4 GiB: nothing the control unit sends
      continue;
    }
    out.frames.insert(out.frames.end(), next.prelude.begin(), next.prelude.end());
    pending_frame_fault_ = next.first_consecutive_frame;
    sender_counted_ = false;
  }
}

void IsoTpChannel::note_receive(protocol::IsoTpReceiveResult result, IsoTpChannelOutput& out) {
  if (result.flow_control) {
    out.frames.push_back(*result.flow_control);
  }
  if (result.error) {
    // The receiver's own counters name the kinds; the channel counts telegrams lost. A too
    // large first frame is refused (overflow FC) rather than dropped midway, but lost all the same.
    ++counters_.receive_errors;
  }
  if (result.message) {
    ++counters_.telegrams_received;
    out.telegrams.push_back(std::move(*result.message));
  }
}

}  // namespace ldoem::endpoints
