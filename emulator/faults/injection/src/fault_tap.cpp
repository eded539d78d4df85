#include "ldoem/fault_injection/fault_tap.hpp"

#include <algorithm>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/isotp.hpp"

namespace ldoem::fault_injection {

using endpoints::LogLevel;
using protocol::WireDirection;
using endpoints::WireVerdict;
using faults::FaultKind;
using base::SimTime;

namespace {

// The wire faults the tap itself produces (telegram level). The others act inside an endpoint
// through their fault hook (endpoint_faults.hpp): framing, ISO-TP frames, TCP pacing, LPT steps.
constexpr FaultKind kTapKinds[] = {FaultKind::drop_reply, FaultKind::delay_reply, FaultKind::duplicate_reply,
                                   FaultKind::truncate_reply, FaultKind::tcp_reset};

}  // namespace

FaultTap::FaultTap(FaultedDevice& device, endpoints::Scheduler& scheduler, const endpoints::Logger& logger,
                   FaultTapSetup setup, EventSink publish)
    : device_(device), scheduler_(scheduler), logger_(logger), publish_(std::move(publish)) {
  injector_ = std::make_unique<FaultInjector>(std::move(setup.scene_faults), setup.seed, setup.head_dynamics,
                                              device_.control_unit(), setup.boot_time);
  endpoint_faults_ = std::make_unique<EndpointFaults>(*injector_, [this](InjectorOutput output) { take(std::move(output)); });
  device_.set_fault_hook(endpoint_faults_.get());
  device_.set_wire_tap(this);
  take(injector_->advance(scheduler_.now()));
}

FaultTap::~FaultTap() {
  if (deadline_) scheduler_.cancel(*deadline_);
  while (!delayed_.empty()) forget_delayed(delayed_.begin()->first);
  device_.set_fault_hook(nullptr);
  if (device_.wire_tap() == this) device_.set_wire_tap(nullptr);
}

void FaultTap::take(InjectorOutput output) {
  if (!output.actions.telegrams.empty() || !output.actions.timers.empty() || output.actions.flash_image) {
    device_.perform_actions(scheduler_.now(), output.actions);
  }
  for (const Power power : output.power_steps) {
    switch (power) {
      case Power::on: device_.set_power(endpoints::DevicePower::on); break;
      case Power::off: device_.set_power(endpoints::DevicePower::off); break;
      case Power::booting: device_.set_power(endpoints::DevicePower::booting); break;
    }
  }
  for (const auto& event : output.events) publish_(event);
  arm_deadline();
}

void FaultTap::arm_deadline() {
  const std::optional<SimTime> next = injector_->next_deadline();
  if (next == deadline_at_) return;
  if (deadline_) scheduler_.cancel(*deadline_);
  deadline_.reset();
  deadline_at_ = next;
  if (!next) return;
  deadline_ = scheduler_.add(*next, [this](SimTime now) {
    deadline_.reset();
    deadline_at_.reset();
    take(injector_->advance(now));
  });
}

WireVerdict FaultTap::on_telegram(endpoints::WireTelegram& telegram) {
  const protocol::Transport transport = telegram.connection.kind;
  const bool silenced = [&] {
    const faults::ActiveFault* silence = injector_->scheduler().find_active(FaultKind::can_silence);
    return silence && transport == protocol::Transport::can;
  }();
  // Off or booting, the device hears and says nothing (its endpoints are dark as well).
  const bool dark = injector_->power() != Power::on;
  if (telegram.direction == WireDirection::device_to_host) {
    if (dark || silenced) return WireVerdict::drop;
    return to_host(telegram);
  }
  if (dark || silenced) return WireVerdict::drop;
  const std::uint16_t service = telegram.payload.size() >= 2 ? protocol::read_word_be(telegram.payload, 0) : 0;
  // A multi-frame ISO-TP request was seen at its first frame already (EndpointFaults).
  const bool came_in_frames = transport == protocol::Transport::can && telegram.payload.size() > protocol::kIsoTpMaxSingleFrameBytes;
  take(injector_->on_request(telegram.at, service, transport,
                             came_in_frames ? faults::RequestSeen::rest_of_multi_frame : faults::RequestSeen::whole));
  if (injector_->power() != Power::on) return WireVerdict::drop;  // a power cycle this very request started
  return WireVerdict::pass;
}

WireVerdict FaultTap::to_host(endpoints::WireTelegram& telegram) {
  const protocol::Transport transport = telegram.connection.kind;
  const std::uint16_t service = answered_request(telegram.payload);
  std::vector<faults::FaultEvent> used;
  std::optional<faults::ActiveFault> fault;
  for (const FaultKind kind : kTapKinds) {
    fault = injector_->scheduler().take_wire_fault(telegram.at, kind, transport, service, used);
    if (fault) break;
  }
  InjectorOutput output;
  injector_->events_from(used, output);
  // A reply leaves after the request changed the state: STATE_CHANGED goes out with it.
  injector_->note_state(telegram.at, output.events);
  for (const auto& event : output.events) publish_(event);
  if (!fault) return WireVerdict::pass;
  switch (fault->spec.kind) {
    case FaultKind::drop_reply:
      return WireVerdict::drop;
    case FaultKind::delay_reply:
      delay(telegram, fault->spec.delay);
      return WireVerdict::drop;
    case FaultKind::duplicate_reply:
      device_.send_to_host(telegram.connection, telegram.payload, telegram.is_profile);
      return WireVerdict::pass;
    case FaultKind::truncate_reply:
      telegram.payload.resize(std::min<std::size_t>(telegram.payload.size(), fault->spec.bytes_kept));
      return WireVerdict::pass;
    case FaultKind::tcp_reset:
      device_.disconnect(telegram.connection);
      return WireVerdict::drop;
    default:
      return WireVerdict::pass;
  }
}

// Issue 27 D1: the replies held back per connection are bounded (kMaxDelayedTelegrams,
// kMaxDelayedBytes). A reply beyond the bound is lost, as in a device whose send buffer is full:
// counted (delayed_replies_dropped) and warned about at most every 10 s.
void FaultTap::delay(const endpoints::WireTelegram& telegram, SimTime by) {
  const protocol::ConnectionId to = telegram.connection;
  DelayedReplies& held = delayed_[to];
  if (held.pending.size() >= kMaxDelayedTelegrams || held.bytes + telegram.payload.size() > kMaxDelayedBytes) {
    ++delayed_dropped_;
    if (auto line = delayed_warning_.admit("delay_reply: " + protocol::to_string(to) + " already holds " +
                                           std::to_string(held.pending.size()) + " delayed replies (" +
                                           std::to_string(held.bytes) + " bytes); dropping this one")) {
      logger_.log(LogLevel::warn, *line);
    }
    return;
  }
  const std::size_t size = telegram.payload.size();
  auto key = std::make_shared<endpoints::Scheduler::Key>();
  *key = scheduler_.add(telegram.at + by, [this, to, key, size, payload = telegram.payload,
                                           profile = telegram.is_profile](SimTime) {
    release(to, *key, size);
    device_.send_to_host(to, payload, profile);
  });
  held.pending.insert(*key);
  held.bytes += size;
}

void FaultTap::release(protocol::ConnectionId connection, const endpoints::Scheduler::Key& key, std::size_t size) {
  const auto held = delayed_.find(connection);
  if (held == delayed_.end() || held->second.pending.erase(key) == 0) return;
  held->second.bytes -= size;
  if (held->second.pending.empty()) delayed_.erase(held);
}

// A closed connection's delayed replies have nobody to go to: their deadlines go with it.
void FaultTap::forget_delayed(protocol::ConnectionId connection) {
  const auto held = delayed_.find(connection);
  if (held == delayed_.end()) return;
  for (const auto& key : held->second.pending) scheduler_.cancel(key);
  delayed_.erase(held);
}

faults::FaultId FaultTap::inject(const faults::FaultSpec& spec) {
  faults::FaultId id = 0;
  take(injector_->inject(scheduler_.now(), spec, id));
  return id;
}

bool FaultTap::clear(std::optional<faults::FaultId> id) {
  bool found = false;
  take(injector_->clear(scheduler_.now(), id, found));
  return found;
}

}  // namespace ldoem::fault_injection
