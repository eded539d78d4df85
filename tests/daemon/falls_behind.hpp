// What ldoem-emud does when it falls behind real time (docs/decisions-local.md, L-time-1): the
// daemon, streaming at 10 Hz in real time, is stopped with SIGSTOP for a while and resumed. The
// revolutions it could not measure are skipped: PROFILECOUNT jumps, TSTART advances with the
// wall time that passed, PROFILESENT stays consecutive, and nothing queued up is sent late.
// Shared by the TCP/serial tests (host) and the vcan test (inside User-Mode Linux).
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "daemon_process.hpp"
#include "ldoem/driver/endpoint.hpp"

namespace ldoem::daemon::test {

// Streams from `daemon` through `endpoint`, stops the daemon for `stop`, resumes it, and checks
// the profiles on the device's clock (GoogleTest assertions). The only wall-clock figure judged
// is the stop's own length, measured here between the two signals. Prints one line for the
// record ("stopped 301.2 ms: PROFILECOUNT +3, TSTART +300 ms").
void expect_stop_is_skipped(DaemonProcess& daemon, const driver::Endpoint& endpoint, std::chrono::milliseconds stop);

// The minimal scene in `dir`, the daemon in real time (--time-scale 1) with `transport_args`.
std::optional<DaemonProcess> start_real_time_daemon(TempDir& dir, std::vector<std::string> transport_args);

}  // namespace ldoem::daemon::test
