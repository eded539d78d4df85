// The daemon's diagnostic counters (SIGUSR1, and at exit with --log-level info). Each endpoint
// adds its own; the device instance adds the control unit's.
#pragma once

#include <cstdint>
#include <string>

namespace ldoem::endpoints {

struct Counters {
  std::uint64_t telegrams_received = 0;
  std::uint64_t framing_errors = 0;        // TCP/serial frames dropped by the deframers (D2 reason 5)
  std::uint64_t isotp_receive_errors = 0;  // D1: partial telegrams dropped, stray frames
  std::uint64_t isotp_send_failures = 0;   // D1: N_Bs timeout or host overflow
  std::uint64_t isotp_queue_overflows = 0;
  std::uint64_t can_frames_backlogged = 0; // the interface's queue was full
  std::uint64_t can_frames_dropped = 0;    // the backlog behind it was full too (L-limits-2)
  std::uint64_t skipped_profiles = 0;      // D10
  std::uint64_t profiles_sent = 0;
  std::uint64_t tcp_connections = 0;
  std::uint64_t tcp_dropped_slow = 0;      // output queue over its bound
  std::uint64_t tcp_dropped_quiet = 0;     // silent or idle longer than its timeout
  std::uint64_t tcp_refused = 0;           // accepted and closed at once: --max-clients reached
  std::uint64_t serial_overflows = 0;      // serial output discarded: nobody reads the pty
  std::uint64_t lpt_steps = 0;
  std::uint64_t fault_injections = 0;      // D11: faults that became active (scene or control socket)
  std::uint64_t delayed_replies_dropped = 0;  // delay_reply's per-connection bound reached (issue 27)
  std::uint64_t event_log_write_errors = 0;   // --event-log records lost to write errors (issue 27)

  // Field by field (a daemon with several scanners sums its devices').
  Counters& operator+=(const Counters& other);
};

// One line, "counters: telegrams_received=N framing_errors=N ...".
std::string format_counters(const Counters& counters);

}  // namespace ldoem::endpoints
