#include "ldoem/endpoints/can_endpoint.hpp"

#include <cstdio>

#include "ldoem/io/can_interface.hpp"

namespace ldoem::endpoints {
namespace {

// Frames read per loop round: a flooded bus cannot starve the other endpoints.
constexpr int kFramesPerRound = 256;

std::string hex_id(std::uint16_t id) {
  char text[8];
  std::snprintf(text, sizeof text, "%03X", id);
  return text;
}

IsoTpChannelConfig channel_config(const CanIdPair& ids, const protocol::CanConfig& config) {
  IsoTpChannelConfig channel;
  channel.ids = ids;
  channel.block_size = static_cast<std::uint8_t>(config.block_size);
  channel.st_min = std::chrono::milliseconds(config.st_min_ms);
  return channel;
}

}  // namespace

std::optional<OpenFailure> CanHostEndpoint::open(EndpointContext& context) {
  context_ = &context;
  const std::string& name = setup_.interface_name;
  if (auto status = io::check_can_interface(name); !status) {
    return OpenFailure{true, status.error().message()};
  }
  auto socket = io::CanRawSocket::open(name);
  if (!socket) {
    return OpenFailure{true, socket.error().message()};
  }
  socket_.emplace(std::move(*socket));
  if (setup_.bus_timing) {
    pacer_.emplace(can_bit_rate_bps(setup_.config.bitrate_code));  // D1 BITRATE, D9
  }
  std::vector<CanIdPair> pairs = setup_.pairs;
  if (pairs.empty()) {
    pairs.push_back(CanIdPair{setup_.config.request_id, setup_.config.response_id});  // D1 via flash
  }
  for (const CanIdPair& pair : pairs) {
    channels_.emplace_back(channel_config(pair, setup_.config));
    scheduled_polls_.emplace_back();
    held_.emplace_back();
  }
  set_filters();
  if (auto failure = watch_readable(context, socket_->fd(), [this](io::Readiness r) { on_ready(r); })) return failure;
  for (const IsoTpChannel& channel : channels_) {
    context.out << "can " << name << ' ' << hex_id(channel.config().ids.request_id) << ':'
                << hex_id(channel.config().ids.response_id) << '\n';
  }
  return std::nullopt;
}

bool CanHostEndpoint::busy(ConnectionId connection) const {
  if (connection.index < 1 || connection.index > channels_.size()) return false;
  const IsoTpChannel& channel = channels_[connection.index - 1];
  // With bus_timing a telegram is still being sent while its frames wait for the bus.
  return channel.busy() || (pacer_ && pacer_->pending_for(channel.config().ids.response_id));
}

bool CanHostEndpoint::waiting_for_host() const {
  for (const auto& held : held_) {
    if (held) return true;  // D11 isotp_fc_wait: the host waits on our WAITs, alive
  }
  for (const IsoTpChannel& channel : channels_) {
    // A host cannot answer a frame the paced bus has not delivered yet: jump to its release.
    const bool frames_on_the_way = pacer_ && pacer_->pending_for(channel.config().ids.response_id);
    if (channel.waiting_for_host() && !frames_on_the_way) return true;
  }
  return false;
}

void CanHostEndpoint::on_ready(io::Readiness readiness) {
  ++context_->activity;
  if (readiness.writable) {
    flush_backlog();
  }
  for (int frames_this_round = 0; frames_this_round < kFramesPerRound; ++frames_this_round) {
    auto frame = socket_->receive();
    if (!frame) {
      context_->logger.log(LogLevel::warn, frame.error().message());
      return;
    }
    if (!frame->has_value()) return;
    if (dark_) continue;  // D11 power_cycle: heard by nobody
    for (std::size_t channel = 0; channel < channels_.size(); ++channel) {
      if (channels_[channel].accepts(**frame)) {
        if (fault_hook_ != nullptr && first_frame_faulted(channel, **frame)) break;
        handle_input(channel, channels_[channel].on_frame(context_->scheduler.now(), **frame));
        break;
      }
    }
  }
}

void CanHostEndpoint::handle_input(std::size_t channel, IsoTpChannelOutput output) {
  transmit(channel, output.frames);
  for (const protocol::Bytes& telegram : output.telegrams) {
    context_->sink.on_telegram(ConnectionId{protocol::Transport::can, static_cast<std::uint32_t>(channel + 1)}, telegram);
  }
}

void CanHostEndpoint::send(ConnectionId to, protocol::ByteView payload) {
  const std::size_t channel = to.index - 1;
  if (to.index < 1 || channel >= channels_.size() || dark_) return;
  const SimTime now = context_->scheduler.now();
  IsoTpChannelOutput output = fault_hook_ == nullptr
                                  ? channels_[channel].send(now, payload)
                                  : channels_[channel].send(now, payload, fault_hook_->on_outgoing_telegram(to, payload, now));
  transmit(channel, output.frames);
  // The output path never delivers: a telegram completed on the way is handed in at once, but
  // from the scheduler, after this send has returned.
  if (!output.telegrams.empty()) {
    context_->scheduler.add(context_->scheduler.now(), [this, channel, telegrams = std::move(output.telegrams)](SimTime) {
      for (const protocol::Bytes& telegram : telegrams) {
        context_->sink.on_telegram(ConnectionId{protocol::Transport::can, static_cast<std::uint32_t>(channel + 1)}, telegram);
      }
    });
  }
}

void CanHostEndpoint::transmit(std::size_t channel, const std::vector<protocol::CanFrame>& frames) {
  if (pacer_) {
    const SimTime at = context_->scheduler.now();
    // Frames waiting for the paced bus and for the socket share the backlog's bound.
    if (frames.size() + pacer_->size() + backlog_.size() > backlog_.max_frames()) {
      note_dropped_frames(frames.size());
    } else {
      for (const protocol::CanFrame& frame : frames) {
        pacer_->push(at, frame);
      }
    }
    release_paced_frames(at);
  } else {
    if (!backlog_.push(frames)) note_dropped_frames(frames.size());
    flush_backlog();
  }
  schedule_poll(channel);
}

void CanHostEndpoint::schedule_poll(std::size_t channel) {
  if (channel >= channels_.size()) return;
  const auto due = channels_[channel].deadline();
  auto& scheduled = scheduled_polls_[channel];
  if (scheduled && due && scheduled->first == *due) return;
  // Exactly the channel's own deadline stays queued: a transfer that ended (or a timer that moved)
  // leaves no stale poll behind, which with virtual time would jump the clock by N_Bs/N_Cr (D1,
  // D7) after every multi-frame telegram, so that a scan over CAN would see other revolutions
  // (and other D6 noise) than the same scan over TCP.
  if (scheduled) {
    context_->scheduler.cancel(*scheduled);
    scheduled.reset();
  }
  if (!due) return;
  scheduled = context_->scheduler.add(*due, [this, channel](SimTime now_at) {
    scheduled_polls_[channel].reset();  // this entry has just been taken off the queue
    handle_input(channel, channels_[channel].poll(now_at));
  });
}

// D9 bus_timing: frames whose last bit is on the bus go to the socket; the next one is a deadline.
void CanHostEndpoint::release_paced_frames(SimTime at) {
  const std::vector<protocol::CanFrame> due_frames = pacer_->take_due(at);
  if (!backlog_.push(due_frames)) note_dropped_frames(due_frames.size());
  flush_backlog();
  const std::optional<SimTime> due = pacer_->deadline();
  if (!due || (pacer_scheduled_ && *pacer_scheduled_ <= *due)) return;
  pacer_scheduled_ = *due;
  context_->scheduler.add(*due, [this, scheduled_for = *due](SimTime now_at) {
    if (pacer_scheduled_ == scheduled_for) pacer_scheduled_.reset();
    release_paced_frames(now_at);
  });
}

void CanHostEndpoint::flush_backlog() {
  while (!backlog_.empty()) {
    auto sent = socket_->send(backlog_.front());
    if (!sent) {
      context_->logger.log(LogLevel::warn, sent.error().message());
      backlog_.pop_front();
      continue;
    }
    if (*sent == io::SendOutcome::queue_full) {
      ++context_->counters.can_frames_backlogged;
      break;
    }
    backlog_.pop_front();
  }
  (void)context_->loop.change_interest(socket_->fd(), backlog_.empty() ? io::Interest::readable
                                                                       : io::Interest::readable | io::Interest::writable);
}

void CanHostEndpoint::note_dropped_frames(std::size_t count) {
  context_->counters.can_frames_dropped += count;
  context_->logger.log(LogLevel::info, "can: " + std::to_string(count) + " frames dropped, backlog full (" +
                                           std::to_string(backlog_.max_frames()) + " frames: the bus takes nothing)");
}

void CanHostEndpoint::apply_can_config(const protocol::CanConfig& config) {
  if (pacer_) {
    pacer_->set_bit_rate(can_bit_rate_bps(config.bitrate_code));  // frames from now on (D1, D9)
  }
  // D1: SET_CONFIG key 0x0002 (or a reset to flash) moves the first host's pair and sets our
  // BS/STmin; the reply that confirmed it already left on the old identifiers.
  for (std::size_t channel = 0; channel < channels_.size(); ++channel) {
    const CanIdPair ids = channel == 0 ? CanIdPair{config.request_id, config.response_id}
                                       : channels_[channel].config().ids;
    renew_channel(channel, channel_config(ids, config));
  }
  set_filters();
  context_->logger.log(LogLevel::info, "can pair 1 now " + hex_id(config.request_id) + ":" + hex_id(config.response_id));
}

void CanHostEndpoint::renew_channel(std::size_t channel, const IsoTpChannelConfig& config) {
  const IsoTpChannelCounters& old = channels_[channel].counters();
  retired_.receive_errors += old.receive_errors;
  retired_.send_failures += old.send_failures;
  retired_.queue_overflows += old.queue_overflows;
  channels_[channel] = IsoTpChannel(config);
  if (held_[channel]) release_held_first_frame(channel, false);
  if (scheduled_polls_[channel]) context_->scheduler.cancel(*scheduled_polls_[channel]);
  scheduled_polls_[channel].reset();
}

void CanHostEndpoint::set_filters() {
  std::vector<io::CanIdFilter> filters;
  for (const IsoTpChannel& channel : channels_) {
    filters.push_back(io::exact_standard_id(channel.config().ids.request_id));
  }
  if (auto status = socket_->set_filters(filters); !status) {
    context_->logger.log(LogLevel::warn, status.error().message());
  }
}

void CanHostEndpoint::add_counters(Counters& counters) const {
  IsoTpChannelCounters sum = retired_;
  for (const IsoTpChannel& channel : channels_) {
    sum.receive_errors += channel.counters().receive_errors;
    sum.send_failures += channel.counters().send_failures;
    sum.queue_overflows += channel.counters().queue_overflows;
  }
  counters.isotp_receive_errors += sum.receive_errors;
  counters.isotp_send_failures += sum.send_failures;
  counters.isotp_queue_overflows += sum.queue_overflows;
}

}  // namespace ldoem::endpoints
