// One device's fault machinery on the wire (D11), built only when the scene names faults or
// --control/--event-log is given (D9: a scene without faults pays nothing). It is the device's
// WireTap: it counts requests for the triggers, applies the telegram-level wire faults
// (drop, delay, duplicate, truncate, tcp_reset), and keeps the device silent while powered off or
// booting (its endpoints go dark too: FaultedDevice::set_power). It gives the endpoints their
// fault hook (endpoint_faults.hpp) for the faults below the telegram, and drives the
// FaultInjector from the daemon's simulated clock. What it has to say (FAULT_INJECTED, POWER_OFF,
// STATE_CHANGED, ...) goes to an EventSink: the monitor's event bus in the daemon.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "ldoem/base/warning_throttle.hpp"
#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/endpoints/logger.hpp"
#include "ldoem/endpoints/scheduler.hpp"
#include "ldoem/endpoints/wire_tap.hpp"
#include "ldoem/fault_injection/endpoint_faults.hpp"
#include "ldoem/fault_injection/fault_injector.hpp"

namespace ldoem::fault_injection {

// delay_reply (issue 27 D1): replies held back at once per connection, at most this many and
// this many bytes (64 full-size profiles, as a TCP connection's output queue). Beyond: dropped.
inline constexpr std::size_t kMaxDelayedTelegrams = 64;
inline constexpr std::size_t kMaxDelayedBytes = 64 * 5825;

// What the tap needs of the device it acts on (the daemon's DeviceInstance, through an adapter).
class FaultedDevice {
 public:
  virtual ~FaultedDevice() = default;
  // The injector acts on the control unit directly and hands the Actions it got back here.
  virtual control::ControlUnit& control_unit() = 0;
  virtual void perform_actions(base::SimTime at, const control::Actions& actions) = 0;
  // Every endpoint goes dark, resets its old connections, serves again.
  virtual void set_power(endpoints::DevicePower power) = 0;
  // For a delayed, duplicated or reset reply: these do not pass the tap again.
  virtual void send_to_host(protocol::ConnectionId to, protocol::ByteView payload, bool is_profile) = 0;
  virtual void disconnect(protocol::ConnectionId connection) = 0;
  // The seams the tap plugs into (null: unplugged).
  virtual void set_wire_tap(endpoints::WireTap* tap) = 0;
  virtual endpoints::WireTap* wire_tap() const = 0;
  virtual void set_fault_hook(endpoints::WireFaultHook* hook) = 0;
};

// The injector's events, told as they happen.
using EventSink = std::function<void(const InjectorEvent&)>;

struct FaultTapSetup {
  std::vector<faults::FaultSpec> scene_faults;
  std::uint64_t seed = 0;
  bool head_dynamics = false;  // D9 head_dynamics: a stall coasts down
  base::SimTime boot_time{};   // scanner.boot_s
};

class FaultTap final : public endpoints::WireTap {
 public:
  // Plugs itself into `device` as its wire tap and fault hook, then catches up with the clock
  // (faults due at time 0). `device`, `scheduler` and `logger` must outlive it.
  FaultTap(FaultedDevice& device, endpoints::Scheduler& scheduler, const endpoints::Logger& logger,
           FaultTapSetup setup, EventSink publish);
  ~FaultTap() override;
  FaultTap(const FaultTap&) = delete;
  FaultTap& operator=(const FaultTap&) = delete;

  // --- WireTap ---
  endpoints::WireVerdict on_telegram(endpoints::WireTelegram& telegram) override;

  // A connection closed: its delayed replies have nobody to go to.
  void forget_delayed(protocol::ConnectionId connection);

  // The control socket's fault commands. inject: the id (0 when the entry waits for a trigger).
  faults::FaultId inject(const faults::FaultSpec& spec);
  // clear-fault: one (false when there is no such fault) or all.
  bool clear(std::optional<faults::FaultId> id);
  nlohmann::json query_faults() const { return injector_->query_faults(); }
  Power power() const { return injector_->power(); }
  std::size_t faults_active() const { return injector_->scheduler().active().size(); }
  std::uint64_t injections() const { return injector_->injections(); }
  std::uint64_t delayed_replies_dropped() const { return delayed_dropped_; }

 private:
  void take(InjectorOutput output);
  void arm_deadline();
  endpoints::WireVerdict to_host(endpoints::WireTelegram& telegram);
  void delay(const endpoints::WireTelegram& telegram, base::SimTime by);
  void release(protocol::ConnectionId connection, const endpoints::Scheduler::Key& key, std::size_t size);

  FaultedDevice& device_;
  endpoints::Scheduler& scheduler_;
  const endpoints::Logger& logger_;
  EventSink publish_;
  std::unique_ptr<FaultInjector> injector_;
  std::unique_ptr<EndpointFaults> endpoint_faults_;  // the endpoints' fault hook
  std::optional<endpoints::Scheduler::Key> deadline_;
  std::optional<base::SimTime> deadline_at_;
  struct DelayedReplies {
    std::set<endpoints::Scheduler::Key> pending;  // deadlines of the held replies
    std::size_t bytes = 0;
  };
  std::map<protocol::ConnectionId, DelayedReplies> delayed_;  // delay_reply's held replies
  std::uint64_t delayed_dropped_ = 0;
  base::WarningThrottle delayed_warning_{std::chrono::seconds(10)};
};

}  // namespace ldoem::fault_injection
