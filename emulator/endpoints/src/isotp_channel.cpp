#include "ldoem/endpoints/isotp_channel.hpp"

#include <algorithm>

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
    queue_.emplace_back(telegram.begin(), telegram.end());
  }
  pump(now, out);
  return out;
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
      out.frames.insert(out.frames.end(), polled.frames.begin(), polled.frames.end());
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
    const protocol::Bytes next = std::move(queue_.front());
    queue_.pop_front();
    if (auto started = sender_.start(now, next); !started) {
      ++counters_.send_failures;  // empty or over 4 GiB: nothing the control unit sends
      continue;
    }
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
