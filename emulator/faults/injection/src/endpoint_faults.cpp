#include "ldoem/fault_injection/endpoint_faults.hpp"

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/isotp.hpp"
#include "ldoem/protocol/service_codes.hpp"

namespace ldoem::fault_injection {

using endpoints::ConsecutiveFrameFault;
using endpoints::FirstFrameFault;
using faults::FaultKind;
using protocol::Transport;
using base::SimTime;

namespace {

// An open-ended tcp_stall (no duration) is asked about again this often: it ends when cleared.
constexpr SimTime kOpenStallRecheck = std::chrono::milliseconds(100);

}  // namespace


std::uint16_t answered_request(protocol::ByteView payload) {
  if (payload.size() < 2) return 0;
  const std::uint16_t code = protocol::read_word_be(payload, 0);
  if (code == protocol::code_of(protocol::Service::service_failure)) {
    return payload.size() >= 4 ? protocol::read_word_be(payload, 2) : 0;
  }
  return static_cast<std::uint16_t>(code & ~protocol::kResponseBit);
}

std::optional<faults::ActiveFault> EndpointFaults::take(SimTime now, FaultKind kind, Transport transport,
                                                        std::optional<std::uint16_t> service) {
  if (!faults::applies_to(kind, transport)) return std::nullopt;
  std::vector<faults::FaultEvent> used;
  auto fault = injector_.scheduler().take_wire_fault(now, kind, transport, service, used);
  if (!used.empty()) {
    InjectorOutput output;
    injector_.events_from(used, output);
    take_(std::move(output));
  }
  return fault;
}

endpoints::TelegramFaults EndpointFaults::on_outgoing_telegram(protocol::ConnectionId to, protocol::ByteView payload,
                                                               SimTime now) {
  endpoints::TelegramFaults out;
  if (injector_.scheduler().active().empty()) return out;
  const Transport transport = to.kind;
  const std::uint16_t service = answered_request(payload);
  if (take(now, FaultKind::corrupt_checksum, transport, service)) out.corrupt_checksum = true;
  if (const auto garbage = take(now, FaultKind::garbage, transport, service)) {
    out.garbage_before = faults::fault_garbage(injector_.scheduler().seed(), garbage->id, garbage->spec.garbage_bytes);
  }
  // Only a message with consecutive frames can lose one: single frames leave the fault waiting.
  if (transport == Transport::can && payload.size() > protocol::kIsoTpMaxSingleFrameBytes) {
    constexpr std::pair<FaultKind, ConsecutiveFrameFault> kFrameFaults[] = {
        {FaultKind::isotp_drop_cf, ConsecutiveFrameFault::drop},
        {FaultKind::isotp_repeat_cf, ConsecutiveFrameFault::repeat},
        {FaultKind::isotp_bad_sn, ConsecutiveFrameFault::bad_sequence}};
    for (const auto& [kind, effect] : kFrameFaults) {
      if (take(now, kind, transport, service)) {
        out.first_consecutive_frame = effect;
        break;
      }
    }
  }
  return out;
}

std::optional<SimTime> EndpointFaults::stalled_until(protocol::ConnectionId connection, SimTime now) {
  const faults::ActiveFault* stall = injector_.scheduler().find_active_on(now, FaultKind::tcp_stall, connection.kind);
  if (stall == nullptr) return std::nullopt;
  return stall->until ? *stall->until : now + kOpenStallRecheck;
}

std::optional<std::uint32_t> EndpointFaults::bytes_per_second(protocol::ConnectionId connection, SimTime now) {
  const faults::ActiveFault* limit = injector_.scheduler().find_active_on(now, FaultKind::bandwidth, connection.kind);
  if (limit == nullptr) return std::nullopt;
  return limit->spec.bytes_per_s;
}

FirstFrameFault EndpointFaults::on_host_first_frame(protocol::ConnectionId from, std::uint16_t service, SimTime now) {
  const Transport transport = from.kind;
  // The request's triggers of the first-frame kinds count it here, so that `on: {service, nth}`
  // refuses or holds that very request; the others count it once it is complete (FaultTap::on_telegram).
  take_(injector_.on_request(now, service, transport, faults::RequestSeen::first_frame));
  if (take(now, FaultKind::isotp_fc_overflow, transport, service)) return FirstFrameFault::overflow;
  if (take(now, FaultKind::isotp_fc_wait, transport, service)) return FirstFrameFault::wait;
  return FirstFrameFault::none;
}

bool EndpointFaults::keeps_host_waiting(protocol::ConnectionId from, SimTime now) {
  return injector_.scheduler().find_active_on(now, FaultKind::isotp_fc_wait, from.kind) != nullptr;
}

bool EndpointFaults::loses_step(SimTime at) {
  if (injector_.scheduler().find_active_on(at, FaultKind::lpt_jam, Transport::lpt) != nullptr) return true;
  return take(at, FaultKind::lpt_lose_steps, Transport::lpt, std::nullopt).has_value();
}

}  // namespace ldoem::fault_injection
