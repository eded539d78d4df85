// D11 isotp_fc_overflow and isotp_fc_wait inside the CAN endpoint (wire_fault_hook.hpp): the
// answer to a host's first frame. Only reached when the daemon set a fault hook. And
// power_cycle (set_power, docs/decisions-local.md L-faults-5), called only by the fault machinery.
#include "ldoem/endpoints/can_endpoint.hpp"

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::endpoints {
namespace {

// isotp_fc_wait: another FC WAIT every half N_Bs (D1: 1 s), so that a host that restarts N_Bs on
// each WAIT (ISO 15765-2) keeps waiting for as long as the fault lasts.
constexpr SimTime kFlowControlWaitPeriod = std::chrono::milliseconds(500);

}  // namespace

protocol::CanFrame CanHostEndpoint::flow_control(std::size_t channel, protocol::IsoTpFlowStatus status) const {
  const IsoTpChannelConfig& config = channels_[channel].config();
  return protocol::make_flow_control_frame(config.ids.response_id, status, 0, 0, config.pad_frames);
}

bool CanHostEndpoint::first_frame_faulted(std::size_t channel, const protocol::CanFrame& frame) {
  const auto type = protocol::isotp_frame_type(frame);
  if (held_[channel] && type != protocol::IsoTpFrameType::flow_control) {
    release_held_first_frame(channel, false);  // the host gave up waiting and sends something new
  }
  if (type != protocol::IsoTpFrameType::first_frame) return false;
  const ConnectionId from{protocol::Transport::can, static_cast<std::uint32_t>(channel + 1)};
  // A first frame's data: PCI (2 bytes), then the message's first bytes, the service code first.
  // (A first frame too short to carry it is broken; the channel drops it: service 0, none.)
  const std::uint16_t service = frame.length >= 4 ? protocol::read_word_be(frame.data, 2) : std::uint16_t{0};
  switch (fault_hook_->on_host_first_frame(from, service, context_->scheduler.now())) {
    case FirstFrameFault::none:
      return false;
    case FirstFrameFault::overflow:
      // `32 00 00`: the message is refused; its consecutive frames, if the host sends them
      // anyway, are stray frames to the receiver.
      transmit(channel, {flow_control(channel, protocol::IsoTpFlowStatus::overflow)});
      return true;
    case FirstFrameFault::wait:
      held_[channel] = HeldFirstFrame{frame, std::nullopt};
      keep_host_waiting(channel);
      return true;
  }
  return false;
}

// `31 00 00` now and every kFlowControlWaitPeriod while the fault lasts; then the first frame
// goes to the channel, whose flow control lets the host go on.
void CanHostEndpoint::keep_host_waiting(std::size_t channel) {
  HeldFirstFrame& held = *held_[channel];
  held.next_wait.reset();
  transmit(channel, {flow_control(channel, protocol::IsoTpFlowStatus::wait)});
  // A WAIT is for a host to answer in its own (wall) time: with --virtual-time the daemon gives it
  // the grace it gives a host it waits for (D7) before jumping to the next WAIT, instead of
  // jumping there at once and flooding the bus with WAITs as fast as it can while the fault lasts.
  ++context_->activity;
  held.next_wait = context_->scheduler.add(context_->scheduler.now() + kFlowControlWaitPeriod, [this, channel](SimTime now) {
    if (!held_[channel]) return;
    held_[channel]->next_wait.reset();
    const ConnectionId from{protocol::Transport::can, static_cast<std::uint32_t>(channel + 1)};
    if (fault_hook_->keeps_host_waiting(from, now)) {
      keep_host_waiting(channel);
    } else {
      release_held_first_frame(channel, true);
    }
  });
}

void CanHostEndpoint::release_held_first_frame(std::size_t channel, bool deliver) {
  if (!held_[channel]) return;
  const HeldFirstFrame held = std::move(*held_[channel]);
  held_[channel].reset();
  if (held.next_wait) context_->scheduler.cancel(*held.next_wait);
  if (deliver) handle_input(channel, channels_[channel].on_frame(context_->scheduler.now(), held.frame));
}

void CanHostEndpoint::set_power(DevicePower power) {
  const bool was_dark = dark_;
  dark_ = power != DevicePower::on;
  if (!dark_ || was_dark || context_ == nullptr) return;
  for (std::size_t channel = 0; channel < channels_.size(); ++channel) {
    renew_channel(channel, channels_[channel].config());
  }
  while (!backlog_.empty()) backlog_.pop_front();  // lost with the controller's memory
  if (pacer_) (void)pacer_->take_due(SimTime::max());
  (void)context_->loop.change_interest(socket_->fd(), io::Interest::readable);
}

}  // namespace ldoem::endpoints
