// One LD-OEM in the daemon: its device model (control/device_model.hpp), and the endpoints hosts
// reach it through. The model is an emulated control unit with its plant
// (emulator/physics/plant), or a recorded device (emulator/device/replay, --replay) with no plant:
// the tilt stepper's writes are then accepted and counted. Several instances can share one scene
// world (several scanners in one daemon): each has its own plant, flash and endpoints, and all use
// the daemon's loop and clock.
//
// The instance is the endpoints' sink and the model's TransportQuery, and the control unit's
// FlashStore (a flash write is stored before its reply is built). It performs what the model returns
// (Actions) and nothing else: telegrams to the endpoints (through the WireTap when one is set),
// timers to the scheduler (stale ones cancelled), a new head target to the plant, a new CAN
// configuration to the endpoints. Input that
// arrives while Actions are being performed (a connection that a send dropped) waits until they
// are done: no call re-enters the model from its own output.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string_view>
#include <vector>

#include "ldoem/control/control_unit.hpp"
#include "ldoem/control/device_model.hpp"
#include "ldoem/control/flash_image.hpp"
#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/endpoints/wire_tap.hpp"
#include "ldoem/plant/scene_plant.hpp"

namespace ldoem::daemon {

using endpoints::Counters;
using endpoints::HostEndpoint;

class DeviceInstance final : public endpoints::EndpointSink,
                             public endpoints::LptSink,
                             private control::TransportQuery,
                             private control::FlashStore {
 public:
  // Builds the plant on `world` and the control unit powered up with `flash_config` (what
  // `flash` holds, or the scene's defaults, D4). `scene`, `world`, `scheduler` and `logger` must
  // outlive the instance. Its beams pass through `own_housing` (issue 15, scene/scanners.hpp).
  DeviceInstance(const scene::Scene& scene, plant::SceneWorld& world, std::unique_ptr<control::FlashStore> flash,
                 const control::DeviceConfig& flash_config, endpoints::Scheduler& scheduler,
                 const endpoints::Logger& logger, std::optional<std::uint32_t> own_housing = std::nullopt);
  // Another model (a recorded device): no plant, no flash.
  DeviceInstance(std::unique_ptr<control::DeviceModel> model, endpoints::Scheduler& scheduler,
                 const endpoints::Logger& logger);
  ~DeviceInstance() override;

  // The CAN configuration in RAM at power-up, for the CAN endpoint's first pair (D1).
  const protocol::CanConfig& can_config() const { return model_->can_config(); }

  // Before open_endpoints(): at most one endpoint per transport kind.
  void add_endpoint(std::unique_ptr<HostEndpoint> endpoint);
  [[nodiscard]] std::optional<endpoints::OpenFailure> open_endpoints(io::EventLoop& loop, std::ostream& out,
                                                                     std::uint64_t& activity);
  // Whether a host can reach the device: some endpoint carries telegrams (the LPT does not).
  bool has_host_transport() const;
  // The first endpoint called `name` ("tcp", "can", "memory", ...), or null.
  HostEndpoint* endpoint(std::string_view name) const;

  // Every telegram in and out passes `tap` (null: none). The tap must outlive the instance.
  void set_wire_tap(endpoints::WireTap* tap) { tap_ = tap; }
  // D11 faults below the telegram: `hook` goes to every endpoint (null: none). It must outlive them
  // or be unset first.
  void set_fault_hook(endpoints::WireFaultHook* hook) {
    for (const auto& endpoint : endpoints_) endpoint->set_fault_hook(hook);
  }
  endpoints::WireTap* wire_tap() const { return tap_; }
  // For a tap that delays or resets: these do not pass the tap again.
  void deliver_from_host(protocol::ConnectionId from, protocol::Bytes payload);
  void send_to_host(protocol::ConnectionId to, protocol::ByteView payload, bool is_profile);
  void disconnect(protocol::ConnectionId connection);
  // D11 power_cycle: every endpoint goes dark, resets its old connections, serves again.
  void set_power(endpoints::DevicePower power) {
    for (const auto& endpoint : endpoints_) endpoint->set_power(power);
  }

  bool waiting_for_host() const;
  // Flushes the endpoints and saves the flash (at exit). False when the flash was not saved
  // (the error is logged): the daemon then exits 1.
  [[nodiscard]] bool close();
  Counters counters() const;
  const control::DeviceModel& model() const { return *model_; }
  // The emulated control unit; null for a recorded device.
  const control::ControlUnit* control_unit() const { return unit_; }
  // The fault machinery (D11, fault_tap.hpp) acts on the control unit directly and hands the
  // Actions it got back here, like any other event's. Only for a control unit: a recorded device
  // gets no FaultTap (supervision.cpp).
  control::ControlUnit& unit_for_faults() { return *unit_; }
  void perform_actions(base::SimTime at, const control::Actions& actions) { perform(at, actions); }

  // --- EndpointSink ---
  void on_telegram(protocol::ConnectionId from, protocol::Bytes payload) override;
  void on_framing_error(protocol::ConnectionId from, const protocol::FramingError& error) override;
  void on_connection_closed(protocol::ConnectionId connection) override;
  void on_connection_opened(protocol::ConnectionId connection, std::string_view peer) override;
  // Told of every host connection opened and closed (the control socket's CONNECTION events).
  using ConnectionObserver = std::function<void(bool opened, protocol::ConnectionId connection, std::string_view peer)>;
  void set_connection_observer(ConnectionObserver observer) { connection_observer_ = std::move(observer); }
  // --- LptSink ---
  void on_register_write(base::SimTime at, std::uint8_t register_value) override;
  void set_initial_register(std::uint8_t register_value) override {
    if (plant_) plant_->set_initial_register(register_value);
  }
  void on_line_change(base::SimTime at, std::uint8_t bit, bool level) override;
  std::uint64_t steps_seen() const override;

 private:
  bool busy(protocol::ConnectionId connection) const override;  // D10, asked by the model
  // The control unit's flash store: a write the file store refuses is logged, and the unit
  // answers the service's error (L-flash-1).
  protocol::Bytes load() const override { return flash_->load(); }
  Saved save(protocol::ByteView image) override;
  // Runs `input` now, or after the Actions being performed when called from inside them.
  void accept_input(std::function<void()> input);
  void perform(base::SimTime at, const control::Actions& actions);

  endpoints::Scheduler& scheduler_;
  const endpoints::Logger& logger_;
  std::optional<plant::ScenePlant> plant_;  // none for a recorded device
  std::unique_ptr<control::FlashStore> flash_;
  std::unique_ptr<control::DeviceModel> model_;
  control::ControlUnit* unit_ = nullptr;  // model_ when it is the emulated control unit
  std::uint64_t lpt_writes_ = 0;          // without a plant: the stepper's writes, counted
  std::vector<std::unique_ptr<HostEndpoint>> endpoints_;
  std::map<protocol::Transport, HostEndpoint*> route_;
  std::map<std::uint64_t, endpoints::Scheduler::Key> timer_keys_;  // the control unit's queued timers
  std::optional<endpoints::EndpointContext> context_;
  endpoints::WireTap* tap_ = nullptr;
  std::optional<protocol::ConnectionId> resetting_;  // inside disconnect(): its close is a reset
  ConnectionObserver connection_observer_;
  int performing_ = 0;
  std::deque<std::function<void()>> deferred_input_;
  Counters counters_;
};

}  // namespace ldoem::daemon
