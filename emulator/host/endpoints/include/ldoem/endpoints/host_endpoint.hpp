// One back end of the daemon (QEMU's pluggable chardev back ends; ros2_control's one interface,
// many implementations): TCP, serial pty, CAN with ISO-TP, the LPT pty or gpio lines, or the
// in-memory endpoint of the tests. The device instance knows endpoints only through this
// interface:
//   open(context)  watch its descriptors, print its line(s) ("tcp 127.0.0.1:49152");
//   busy(c)        D10: connection c is still sending the previous telegram;
//   send(c, p)     frame telegram payload p for connection c and write it (one piece, D10);
//   close()        flush what can still go out, stop watching.
// Telegrams from hosts go to the EndpointSink, register writes of the LPT to the LptSink, and
// deadlines are asked of the Scheduler. An endpoint never calls back into the sink from send()
// (no re-entry from the output path into the input path).
//
// Adding a transport: its endpoint here, one line in emulator/daemon/src/endpoint_registry.cpp, and
// the rest docs/architecture.md "What a change touches" lists (13 files in all).
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>

#include "ldoem/control/ports.hpp"
#include "ldoem/endpoints/counters.hpp"
#include "ldoem/endpoints/logger.hpp"
#include "ldoem/endpoints/scheduler.hpp"
#include "ldoem/endpoints/wire_fault_hook.hpp"
#include "ldoem/io/event_loop.hpp"
#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/config.hpp"
#include "ldoem/protocol/framing.hpp"

namespace ldoem::endpoints {

using protocol::ConnectionId;
using protocol::Transport;

// D11 power_cycle as a host sees it (docs/decisions-local.md L-faults-5). `off`: the device is
// dark: no byte read or written, no new connection completed, established ones left as they
// are (no FIN: the host's own timeouts must fire). `booting`: power is back; connections from
// before are reset (RST); still dark. `on`: listening and serving again.
enum class DevicePower : std::uint8_t { on, off, booting };

// Telegrams and connection events from the hosts, to the device.
class EndpointSink {
 public:
  virtual ~EndpointSink() = default;
  virtual void on_telegram(ConnectionId from, protocol::Bytes payload) = 0;
  // D2: a frame the deframer dropped.
  virtual void on_framing_error(ConnectionId from, const protocol::FramingError& error) = 0;
  virtual void on_connection_closed(ConnectionId connection) = 0;
  // A host connected (TCP); `peer` is its address ("127.0.0.1:40112"). For the control socket's
  // CONNECTION_OPENED event; nothing else depends on it.
  virtual void on_connection_opened(ConnectionId /*connection*/, std::string_view /*peer*/) {}
};

// The LPT data register as the tilt stepper's drive board sees it (D8).
class LptSink {
 public:
  virtual ~LptSink() = default;
  // pty back end: every byte is a new register value, stamped with its arrival time.
  virtual void on_register_write(SimTime at, std::uint8_t register_value) = 0;
  // gpio back end: the register before any edge, then line `bit` changed to `level` at `at`.
  virtual void set_initial_register(std::uint8_t register_value) = 0;
  virtual void on_line_change(SimTime at, std::uint8_t bit, bool level) = 0;
  virtual std::uint64_t steps_seen() const = 0;
};

// What an endpoint is given to open: the loop to watch its descriptors in, simulated time, where
// incoming things go, and where to log, print and count.
struct EndpointContext {
  io::EventLoop& loop;
  Scheduler& scheduler;
  EndpointSink& sink;
  LptSink& lpt;
  const Logger& logger;
  std::ostream& out;          // one line per endpoint, read by scripts and tests
  Counters& counters;
  std::uint64_t& activity;    // +1 per descriptor callback and per FC WAIT sent (virtual time: did anything happen?)
};

struct OpenFailure {
  bool usage_error = true;  // the set-up is unusable (exit 2); false: a runtime failure (exit 1)
  std::string message;      // one line: "can: interface vcan0 does not exist"
};

// For open(): watches `fd` readable in the context's loop, or says why it cannot (exit 1).
[[nodiscard]] std::optional<OpenFailure> watch_readable(EndpointContext& context, int fd, io::EventLoop::FdCallback callback,
                                                        io::RoundOrder order = io::kInRoundOrder);

class HostEndpoint {
 public:
  virtual ~HostEndpoint() = default;
  HostEndpoint() = default;
  HostEndpoint(const HostEndpoint&) = delete;
  HostEndpoint& operator=(const HostEndpoint&) = delete;

  virtual std::string_view name() const = 0;
  // The kind of connection this endpoint carries; none for the LPT.
  virtual std::optional<protocol::Transport> transport() const = 0;

  [[nodiscard]] virtual std::optional<OpenFailure> open(EndpointContext& context) = 0;
  virtual bool busy(ConnectionId connection) const = 0;
  virtual void send(ConnectionId to, protocol::ByteView payload) = 0;
  virtual void close() = 0;

  // Drops one connection with a reset on the wire (TCP: RST, D11 tcp_reset); the sink hears of it.
  virtual void disconnect(ConnectionId /*connection*/) {}
  // D11 power_cycle (DevicePower above). Only the fault machinery calls it; an endpoint that
  // keeps no state across telegrams needs nothing (the device's wire tap drops its telegrams).
  virtual void set_power(DevicePower /*power*/) {}
  // A deadline of this endpoint is a timeout on a host that needs wall time to answer (ISO-TP
  // N_Bs/N_Cr): a virtual clock must not jump over it while the host is alive (D1, D7).
  virtual bool waiting_for_host() const { return false; }
  // The control unit's CAN configuration changed (D1: SET_CONFIG key 2, a reset to flash).
  virtual void apply_can_config(const protocol::CanConfig& /*config*/) {}
  // Takes in what has already arrived without waiting for the loop: the device calls it before
  // serving a telegram, for inputs that the host made before the telegram and that must count
  // first (D8: the tilt stepper's register writes).
  virtual void take_pending_input() {}
  // Counts kept inside the endpoint (the ISO-TP channels'), added to `counters` on demand.
  virtual void add_counters(Counters& /*counters*/) const {}

  // D11 wire faults below the telegram (wire_fault_hook.hpp); null (the default): none, at no cost.
  // The hook must outlive the endpoint's use of it.
  void set_fault_hook(WireFaultHook* hook) { fault_hook_ = hook; }

 protected:
  WireFaultHook* fault_hook_ = nullptr;
};

}  // namespace ldoem::endpoints
