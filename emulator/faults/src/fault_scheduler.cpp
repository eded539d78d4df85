#include "ldoem/faults/fault_scheduler.hpp"

#include <algorithm>

namespace ldoem::faults {
namespace {

// SplitMix64's finaliser: a bijective 64-bit mix (the same one D6's noise streams use).
std::uint64_t mix64(std::uint64_t value) {
  value += 0x9E3779B97F4A7C15ULL;
  value = (value ^ (value >> 30)) * 0xBF58476D1CE4E5B9ULL;
  value = (value ^ (value >> 27)) * 0x94D049BB133111EBULL;
  return value ^ (value >> 31);
}

// A different constant from D6's noise key, so that fault draws and range noise never share
// a stream for the same seed.
constexpr std::uint64_t kFaultStreamTag = 0xFA017'0000'0011ULL;

std::optional<std::uint16_t> trigger_service(const Trigger& trigger) {
  if (const auto* on = std::get_if<TriggerOnNth>(&trigger)) return on->service;
  if (const auto* every = std::get_if<TriggerEvery>(&trigger)) return every->service;
  return std::nullopt;
}

}  // namespace

bool acts_on_host_first_frame(FaultKind kind) {
  return kind == FaultKind::isotp_fc_overflow || kind == FaultKind::isotp_fc_wait;
}

double fault_draw(std::uint64_t seed, std::uint64_t entry_index, std::uint64_t request_number) {
  const std::uint64_t bits = mix64(mix64(mix64(seed ^ kFaultStreamTag) + entry_index) + request_number);
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

std::vector<std::uint8_t> fault_garbage(std::uint64_t seed, std::uint64_t id, std::size_t count) {
  constexpr std::uint64_t kGarbageStreamTag = 0x6A5BA6E0'0000'0011ULL;
  constexpr std::uint8_t kFrameStart = 0x02;  // TCP magic's first byte, serial STX
  std::vector<std::uint8_t> bytes(count);
  const std::uint64_t key = mix64(mix64(seed ^ kGarbageStreamTag) + id);
  for (std::size_t i = 0; i < count; ++i) {
    auto byte = static_cast<std::uint8_t>(mix64(key + i) & 0xFF);
    if (byte == kFrameStart) byte = static_cast<std::uint8_t>(~kFrameStart);
    bytes[i] = byte;
  }
  return bytes;
}

FaultScheduler::FaultScheduler(std::vector<FaultSpec> scene_faults, std::uint64_t seed) : seed_(seed) {
  for (std::size_t i = 0; i < scene_faults.size(); ++i) {
    entries_.push_back(Entry{std::move(scene_faults[i]), i, false, 0});
  }
}

void FaultScheduler::activate(SimTime now, FaultSpec spec, std::string origin, std::vector<FaultEvent>& events) {
  // A wire fault triggered by a service's request acts on that service's replies unless the
  // entry names another.
  if (!spec.service && info(spec.kind).fault_class == FaultClass::wire) spec.service = trigger_service(spec.trigger);
  ActiveFault fault;
  fault.id = next_id_++;
  fault.since = now;
  if (spec.duration) fault.until = now + *spec.duration;
  if (spec.count) fault.remaining = *spec.count;
  // With neither, the catalogue says how long it acts: most wire faults on one telegram, a state
  // of the link (tcp_stall, lpt_jam, ...) and a device fault until cleared.
  if (!spec.duration && !spec.count && info(spec.kind).extent == FaultExtent::count_one) fault.remaining = 1;
  fault.spec = std::move(spec);
  fault.origin = origin;
  events.push_back(FaultEvent{now, FaultEventKind::injected, fault.id, fault.spec.kind, std::move(origin)});
  active_.push_back(std::move(fault));
}

void FaultScheduler::remove_at(std::size_t position, SimTime now, std::string reason, std::vector<FaultEvent>& events) {
  const ActiveFault& fault = active_[position];
  events.push_back(FaultEvent{now, FaultEventKind::cleared, fault.id, fault.spec.kind, std::move(reason)});
  active_.erase(active_.begin() + static_cast<std::ptrdiff_t>(position));
}

void FaultScheduler::advance(SimTime now, std::vector<FaultEvent>& events) {
  // Expiries first, in activation order, so that an entry firing at the same instant is not
  // cleared by the previous one's end.
  for (std::size_t i = 0; i < active_.size();) {
    if (active_[i].until && *active_[i].until <= now) {
      remove_at(i, *active_[i].until, "expired", events);
    } else {
      ++i;
    }
  }
  for (Entry& entry : entries_) {
    if (entry.fired) continue;
    const std::string origin = "scene[" + std::to_string(entry.index) + "]";
    if (std::holds_alternative<TriggerNow>(entry.spec.trigger)) {
      entry.fired = true;
      activate(now, entry.spec, origin, events);
    } else if (const auto* at = std::get_if<TriggerAt>(&entry.spec.trigger); at && at->at <= now) {
      entry.fired = true;
      activate(now, entry.spec, origin + " at_s", events);
    }
  }
}

void FaultScheduler::on_request(SimTime now, std::uint16_t service, Transport transport,
                                std::vector<FaultEvent>& events, RequestSeen seen) {
  for (Entry& entry : entries_) {
    const bool first_frame_kind = acts_on_host_first_frame(entry.spec.kind);
    if ((seen == RequestSeen::first_frame && !first_frame_kind) ||
        (seen == RequestSeen::rest_of_multi_frame && first_frame_kind)) {
      continue;
    }
    const std::string origin = "scene[" + std::to_string(entry.index) + "]";
    if (const auto* on = std::get_if<TriggerOnNth>(&entry.spec.trigger)) {
      if (on->service != service) continue;
      if (++entry.matching_requests == on->nth) activate(now, entry.spec, origin + " on", events);
    } else if (const auto* every = std::get_if<TriggerEvery>(&entry.spec.trigger)) {
      if (every->service != service) continue;
      if (++entry.matching_requests % every->count == 0) activate(now, entry.spec, origin + " every", events);
    } else if (const auto* draw = std::get_if<TriggerProbability>(&entry.spec.trigger)) {
      if (entry.spec.service && *entry.spec.service != service) continue;
      if (entry.spec.transport && *entry.spec.transport != transport) continue;
      const std::uint64_t number = entry.matching_requests++;
      if (fault_draw(seed_, entry.index, number) < draw->probability) {
        activate(now, entry.spec, origin + " probability", events);
      }
    }
  }
}

FaultId FaultScheduler::inject(SimTime now, FaultSpec spec, std::vector<FaultEvent>& events) {
  // A control-socket entry with at_s waits like a scene entry; anything else acts now.
  if (std::holds_alternative<TriggerAt>(spec.trigger) || std::holds_alternative<TriggerOnNth>(spec.trigger) ||
      std::holds_alternative<TriggerEvery>(spec.trigger) || std::holds_alternative<TriggerProbability>(spec.trigger)) {
    if (const auto* at = std::get_if<TriggerAt>(&spec.trigger); !at || at->at > now) {
      entries_.push_back(Entry{std::move(spec), entries_.size(), false, 0});
      return 0;
    }
  }
  const FaultId id = next_id_;
  activate(now, std::move(spec), "control", events);
  return id;
}

bool FaultScheduler::clear(SimTime now, FaultId id, std::vector<FaultEvent>& events) {
  for (std::size_t i = 0; i < active_.size(); ++i) {
    if (active_[i].id == id) {
      remove_at(i, now, "cleared", events);
      return true;
    }
  }
  return false;
}

void FaultScheduler::clear_all(SimTime now, std::string_view reason, std::vector<FaultEvent>& events) {
  while (!active_.empty()) remove_at(0, now, std::string(reason), events);
}

bool FaultScheduler::matches(const ActiveFault& fault, Transport transport, std::optional<std::uint16_t> service) const {
  if (!applies_to(fault.spec.kind, transport)) return false;
  if (fault.spec.transport && *fault.spec.transport != transport) return false;
  if (service && fault.spec.service && *fault.spec.service != *service) return false;
  return true;
}

std::optional<ActiveFault> FaultScheduler::take_wire_fault(SimTime now, FaultKind kind, Transport transport,
                                                           std::optional<std::uint16_t> service,
                                                           std::vector<FaultEvent>& events) {
  for (std::size_t i = 0; i < active_.size(); ++i) {
    ActiveFault& fault = active_[i];
    if (fault.spec.kind != kind || !matches(fault, transport, service)) continue;
    if (fault.until && *fault.until <= now) continue;  // advance() clears it
    ActiveFault taken = fault;
    if (fault.remaining && --*fault.remaining == 0) remove_at(i, now, "count used", events);
    return taken;
  }
  return std::nullopt;
}

std::optional<ActiveFault> FaultScheduler::take_any_wire_fault(SimTime now, Transport transport, std::uint16_t service,
                                                               std::vector<FaultEvent>& events) {
  for (const ActiveFault& fault : active_) {
    if (info(fault.spec.kind).fault_class != FaultClass::wire) continue;
    if (!matches(fault, transport, service)) continue;
    return take_wire_fault(now, fault.spec.kind, transport, service, events);
  }
  return std::nullopt;
}

void FaultScheduler::acted(SimTime now, FaultId id, std::vector<FaultEvent>& events) {
  for (std::size_t i = 0; i < active_.size(); ++i) {
    if (active_[i].id == id) {
      remove_at(i, now, "acted", events);
      return;
    }
  }
}

bool FaultScheduler::is_active(FaultKind kind) const { return find_active(kind) != nullptr; }

const ActiveFault* FaultScheduler::find_active(FaultKind kind) const {
  for (const ActiveFault& fault : active_) {
    if (fault.spec.kind == kind) return &fault;
  }
  return nullptr;
}

const ActiveFault* FaultScheduler::find_active_on(SimTime now, FaultKind kind, Transport transport) const {
  for (const ActiveFault& fault : active_) {
    if (fault.spec.kind != kind || !matches(fault, transport, std::nullopt)) continue;
    if (fault.until && *fault.until <= now) continue;
    return &fault;
  }
  return nullptr;
}

std::optional<SimTime> FaultScheduler::next_deadline() const {
  std::optional<SimTime> earliest;
  auto consider = [&earliest](SimTime t) {
    if (!earliest || t < *earliest) earliest = t;
  };
  for (const ActiveFault& fault : active_) {
    if (fault.until) consider(*fault.until);
  }
  for (const Entry& entry : entries_) {
    if (entry.fired) continue;
    if (std::holds_alternative<TriggerNow>(entry.spec.trigger)) consider(SimTime{0});
    if (const auto* at = std::get_if<TriggerAt>(&entry.spec.trigger)) consider(at->at);
  }
  return earliest;
}

}  // namespace ldoem::faults
