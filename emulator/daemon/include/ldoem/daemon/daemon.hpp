// ldoem-emud's wiring (DESIGN.md data flow): one epoll loop, the transport endpoints (CAN with
// ISO-TP, TCP, serial pty), the LPT endpoint (pty or gpio) feeding the tilt motor, the scene's
// models behind the control unit, and the simulated clock (D7) that turns the control unit's
// timers into wall deadlines. Everything that decides something lives in the tested pieces
// (options, sim_clock, isotp_channel, tilt_track, scene_adapters, output_queue); this class
// only moves bytes, frames and time between them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <string>

#include "ldoem/daemon/options.hpp"
#include "ldoem/protocol/expected.hpp"
#include "ldoem/scene/scene.hpp"

namespace ldoem::daemon {

struct StartFailure {
  int exit_code = kExitUsageError;
  std::string message;  // one line: "can: interface vcan0 does not exist"
};

// Counters of the daemon's diagnostics (SIGUSR1, and at exit with --log-level info).
struct DaemonCounters {
  std::uint64_t telegrams_received = 0;
  std::uint64_t framing_errors = 0;        // TCP/serial frames dropped by the deframers (D2 reason 5)
  std::uint64_t isotp_receive_errors = 0;  // D1: partial telegrams dropped, stray frames
  std::uint64_t isotp_send_failures = 0;   // D1: N_Bs timeout or host overflow
  std::uint64_t isotp_queue_overflows = 0;
  std::uint64_t can_frames_backlogged = 0; // the interface's queue was full
  std::uint64_t skipped_profiles = 0;      // D10
  std::uint64_t profiles_sent = 0;
  std::uint64_t tcp_connections = 0;
  std::uint64_t tcp_dropped_slow = 0;      // output queue over its bound
  std::uint64_t serial_overflows = 0;      // serial output discarded: nobody reads the pty
  std::uint64_t lpt_steps = 0;
};

std::string format_counters(const DaemonCounters& counters);

class Daemon {
 public:
  // Builds the scene's models, loads the flash, opens every endpoint and prints one line per
  // endpoint on `out`, then "ready". `log` gets the diagnostics.
  static protocol::Expected<std::unique_ptr<Daemon>, StartFailure> create(Options options, scene::Scene scene,
                                                                          std::ostream& out, std::ostream& log);
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  // Runs until SIGINT/SIGTERM (128 + signal), --count-profiles or --timeout (0), or a fatal
  // loop error (1). Saves the flash before returning.
  int run();

  DaemonCounters counters() const;
  std::optional<std::uint16_t> tcp_port() const;

  struct Impl;

 private:
  explicit Daemon(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldoem::daemon
