// The endpoints' WireFaultHook (endpoints/wire_fault_hook.hpp): the D11 wire faults that act inside
// the endpoints, read from the fault scheduler. The device's FaultTap (fault_tap.hpp) owns it and
// hands it to every endpoint of the device; it exists only when the tap does (D9: no faults, no hook).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "ldoem/endpoints/wire_fault_hook.hpp"
#include "ldoem/fault_injection/fault_injector.hpp"

namespace ldoem::fault_injection {

// The request a telegram to the host answers: its code without the response bit, the request
// code inside a SERVICE_FAILURE, GET_PROFILE for a profile.
std::uint16_t answered_request(protocol::ByteView payload);

class EndpointFaults final : public endpoints::WireFaultHook {
 public:
  // `take` acts on what the injector says (FaultTap::take): the events of a count used up, or
  // of a fault a host's first frame triggered.
  EndpointFaults(FaultInjector& injector, std::function<void(InjectorOutput)> take)
      : injector_(injector), take_(std::move(take)) {}

  endpoints::TelegramFaults on_outgoing_telegram(protocol::ConnectionId to, protocol::ByteView payload,
                                                 base::SimTime now) override;
  std::optional<base::SimTime> stalled_until(protocol::ConnectionId connection, base::SimTime now) override;
  std::optional<std::uint32_t> bytes_per_second(protocol::ConnectionId connection, base::SimTime now) override;
  endpoints::FirstFrameFault on_host_first_frame(protocol::ConnectionId from, std::uint16_t service,
                                                 base::SimTime now) override;
  bool keeps_host_waiting(protocol::ConnectionId from, base::SimTime now) override;
  bool loses_step(base::SimTime at) override;

 private:
  // Takes one telegram's worth of `kind` (its count) and publishes what that used up.
  std::optional<faults::ActiveFault> take(base::SimTime now, faults::FaultKind kind, protocol::Transport transport,
                                          std::optional<std::uint16_t> service);

  FaultInjector& injector_;
  std::function<void(InjectorOutput)> take_;
};

}  // namespace ldoem::fault_injection
