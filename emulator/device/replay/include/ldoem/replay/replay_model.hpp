// The recorded device as a device model (control/device_model.hpp): `ldoem-emud --replay
// CAPTURE` puts it in a DeviceInstance instead of a control unit, behind the daemon's own
// endpoints, scheduler, wire tap and --record (docs/replay.md).
//
// The ReplayDevice says which telegrams answer a request and when; this model hands them out
// per connection in order, one at a time once the endpoint is no longer busy with the previous
// one (D10), through timers at their recorded (scaled) times. A connection that closes forgets
// what was still due for it.
#pragma once

#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>

#include "ldoem/base/expected.hpp"
#include "ldoem/control/device_model.hpp"
#include "ldoem/replay/replay_device.hpp"

namespace ldoem::replay {

class ReplayModel final : public control::DeviceModel {
 public:
  // Told why a request was not in the recording (one line).
  using Warn = std::function<void(const std::string& line)>;
  // `report` gets the counters line at exit; it must outlive the model.
  ReplayModel(ReplayDevice device, Warn warn, std::ostream& report);

  control::Actions handle_request(SimTime now, protocol::ConnectionId from, protocol::ByteView payload,
                                  const control::TransportQuery& transport) override;
  control::Actions on_timer(SimTime now, control::TimerId timer, const control::TransportQuery& transport) override;
  control::Actions on_framing_error(SimTime now, protocol::ConnectionId from,
                                    const protocol::FramingError& error) override;
  control::Actions on_connection_closed(SimTime now, protocol::ConnectionId connection) override;
  // A recording has no RAM: the D1 default identifiers (--can can:IF:REQ:RESP names others).
  const protocol::CanConfig& can_config() const override { return can_; }
  const control::Diagnostics& diagnostics() const override { return diagnostics_; }
  // "ldoem-emud: replay: requests=N in_order=N out_of_order=N unexpected=N".
  void report_at_exit() const override;

  const ReplayCounters& counters() const { return device_.counters(); }

 private:
  // Sends the next telegram due for `connection` unless its endpoint is busy; wakes up for the rest.
  control::Actions pump(SimTime now, protocol::ConnectionId connection, const control::TransportQuery& transport);

  ReplayDevice device_;
  Warn warn_;
  std::ostream& report_;
  protocol::CanConfig can_{};
  control::Diagnostics diagnostics_;
  std::map<protocol::ConnectionId, std::deque<ScheduledTelegram>> outgoing_;
  std::map<protocol::ConnectionId, control::TimerId> wakeups_;
  std::map<control::TimerId, protocol::ConnectionId> woken_;
  std::uint64_t next_timer_ = 1;
};

// What --replay reads: the capture, which recorded transport, the device's TCP port in it, the
// CAN identifiers of its ISO-TP conversation.
struct ReplaySource {
  std::filesystem::path capture;
  std::optional<protocol::Transport> transport;        // default: the busiest one
  std::optional<std::uint16_t> capture_tcp_port;       // default: detected from the frames
  std::optional<std::pair<std::uint16_t, std::uint16_t>> can_ids;  // request, response
};
// The recorded delays are played in device time: the daemon's --time-scale speeds them up.

// Reads and cuts the capture; writes its summary (and a reader's warning) on `report`. The
// error names the file.
[[nodiscard]] base::Expected<std::unique_ptr<ReplayModel>, std::string> load_replay_model(
    const ReplaySource& source, ReplayModel::Warn warn, std::ostream& report);

}  // namespace ldoem::replay
