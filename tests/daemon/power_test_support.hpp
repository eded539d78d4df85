// What the power-cycle tests share (docs/decisions-local.md L-faults-5, L-faults-6): ldoem-emud
// with a control socket as a child process, event times, and a bounded look at what a host hears.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "control_client.hpp"
#include "daemon_process.hpp"

namespace ldoem::daemon::test {

// ldoem-emud on `scene_text` with --control (and `extra` endpoints), --virtual-time or real time.
struct PowerDaemon {
  TempDir dir;
  std::string control_path = dir.path("ctl.sock");
  std::optional<DaemonProcess> process;
  std::optional<ControlClient> control;

  PowerDaemon(const std::string& scene_text, const std::vector<std::string>& extra, bool virtual_time);
  // Started, and the control socket connected (its greeting read).
  bool ready();
  std::string diagnostics() const { return process ? process->stderr_text() : "(not started)"; }
  // power-cycle with `off_s`; true when the daemon accepted it.
  bool power_cycle(double off_s);
  // query-status's "return" object (empty when none came).
  nlohmann::json status();
};

// Device seconds of an event line's timestamp.
double event_seconds(const nlohmann::json& event);

// What the next read of a TCP socket says within `limit`: "bytes", "FIN", "RST" or "nothing".
std::string next_on_tcp(int fd, std::chrono::milliseconds limit);

// connect() to 127.0.0.1:port: "connected", "refused" or the error's text.
std::string try_connect(std::uint16_t port);

// A minimal scene with `scanner_keys` (a YAML flow map body, e.g. "boot_s: 60") added.
std::string scene_with_scanner(const std::string& scanner_keys);

}  // namespace ldoem::daemon::test
