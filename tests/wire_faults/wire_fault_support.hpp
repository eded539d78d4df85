// What the wire-fault tests share: ldoem-emud with a fault scene as a child process or in-process
// with a real TCP listener (so that a test reads simulated time when bytes arrive), and raw reads
// with bounded waits.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "daemon_process.hpp"
#include "host_link.hpp"
#include "ldoem/daemon/daemon.hpp"
#include "ldoem/test_support/raw_tty.hpp"

namespace ldoem::wire_faults::test {

using daemon::test::DaemonProcess;
using daemon::test::TempDir;
using test_support::open_raw;
using protocol::Bytes;

// ldoem-emud on `scene_text` with TCP on a free port (and no CAN unless `extra` says --can),
// `extra` options and its event log in the temporary folder; --virtual-time unless told otherwise.
struct FaultyDaemon {
  TempDir dir;
  std::string event_log = dir.path("events.log");
  std::optional<DaemonProcess> process;

  FaultyDaemon(const std::string& scene_text, const std::vector<std::string>& extra = {}, bool virtual_time = true);
  bool ready() { return process && process->wait_ready(); }
  std::string diagnostics() const { return process ? process->stderr_text() : "(not started)"; }
  std::string events() const;

 private:
  std::vector<std::string> arguments(const std::string& scene_text, const std::vector<std::string>& extra,
                                     bool virtual_time) const;
};

// One request on a fresh connection to the control socket at `path`: its "return" or "error"
// object, or nothing within `limit`.
std::optional<nlohmann::json> control_request(const std::string& path, const nlohmann::json& request,
                                              std::chrono::milliseconds limit = std::chrono::seconds(5));

// Reads until `count` bytes came or `limit` passed; what came.
Bytes read_bytes(int fd, std::size_t count, std::chrono::milliseconds limit = std::chrono::seconds(5));

// The daemon in this process, TCP on a free port, virtual time: the test runs the loop and reads
// simulated time when its bytes arrive.
struct InProcessTcp {
  std::ostringstream out;
  std::ostringstream log;
  std::unique_ptr<daemon::Daemon> daemon;
  std::string failure;

  explicit InProcessTcp(const std::string& scene_text);
  // Runs the loop until `count` bytes came on `fd`; the bytes, and the simulated time of the last.
  struct Arrival {
    Bytes bytes;
    base::SimTime at{};
  };
  Arrival receive(int fd, std::size_t count, std::chrono::milliseconds wall_limit = std::chrono::seconds(20));
  // Runs the loop until `done` or `wall_limit`.
  bool run_until(const std::function<bool()>& done, std::chrono::milliseconds wall_limit = std::chrono::seconds(20)) {
    return daemon->run_until(done, wall_limit);
  }
};

// The determinism tests' check: one conversation run twice gives the same bytes (.first) and the
// same event log (.second); returns the first run for the test's own expectations.
template <typename Run>
auto run_twice_expect_same(const Run& run) {
  auto first = run();
  const auto second = run();
  EXPECT_EQ(first.first, second.first);
  EXPECT_EQ(first.second, second.second);
  return first;
}

}  // namespace ldoem::wire_faults::test
