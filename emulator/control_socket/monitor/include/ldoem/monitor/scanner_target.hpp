// One scanner as the control socket sees it (issue 15: a daemon may serve several): its fault
// commands act on the scanner's FaultTap (emulator/faults), query-status reads the device, and
// its host connections become CONNECTION_OPENED / CONNECTION_CLOSED events on the monitor's bus.
// A recorded device (ldoem-emud --replay) has no control unit and so no FaultTap: its fault
// commands answer kNotForRecorded, query-faults an empty list, query-status state RECORDED.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "ldoem/control/control_unit.hpp"
#include "ldoem/control_socket/control_protocol.hpp"
#include "ldoem/endpoints/counters.hpp"
#include "ldoem/fault_injection/fault_tap.hpp"

namespace ldoem::monitor {

class Monitor;

// What query-status reads of a device (the daemon's DeviceInstance, through an adapter).
class DeviceReadings {
 public:
  virtual ~DeviceReadings() = default;
  // The emulated control unit; null for a recorded device (--replay).
  virtual const control::ControlUnit* unit() const = 0;
  virtual endpoints::Counters counters() const = 0;
  virtual std::uint64_t tilt_steps() const = 0;  // what the tilt plate's drive board counted
};

// What a command that needs a control unit answers for a recorded device (after "COMMAND: ").
inline constexpr std::string_view kNotForRecorded = "not available for a recorded device (--replay)";

class ScannerTarget final : public control_socket::ControlTarget {
 public:
  // `first`: the scanner the commands without "scanner" act on, whose query-status also shows
  // the daemon-wide figures (event log write errors, mesh trees built on the loop). `faults`:
  // null for a recorded device.
  ScannerTarget(Monitor& monitor, std::string name, fault_injection::FaultTap* faults, const DeviceReadings& readings,
                bool first)
      : monitor_(monitor), name_(std::move(name)), faults_(faults), readings_(readings), first_(first) {}

  const std::string& name() const { return name_; }

  // --- ControlTarget ---
  control_socket::CommandResult inject_fault(const faults::FaultSpec& spec) override;
  control_socket::CommandResult clear_fault(std::optional<std::uint64_t> id) override;
  nlohmann::json query_faults() override {
    return faults_ != nullptr ? faults_->query_faults() : nlohmann::json::array();
  }
  nlohmann::json query_status() override;
  void quit() override;

  // A host connection of this scanner opened (with the peer's address) or closed.
  void on_connection(bool opened, protocol::ConnectionId connection, std::string_view peer);

 private:
  Monitor& monitor_;
  std::string name_;  // in the scene (empty: a scanner: section)
  fault_injection::FaultTap* faults_;  // null: a recorded device
  const DeviceReadings& readings_;
  bool first_;
  std::map<protocol::ConnectionId, std::string> peers_;  // open TCP connections' addresses
};

}  // namespace ldoem::monitor
