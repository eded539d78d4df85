// The paper's experiment as the tests run it: a fresh ldoem-emud on scenes/corridor.yaml, an
// optional ldoem-hub in front of it, and one ldoem-scan with the paper's settings
// (docs/paper-reproduction.md). Every scan starts from power-up, so that the same scene, seed and
// command sequence must give the same bytes (D6 noise keyed by seed, revolution and beam).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "e2e_process.hpp"

namespace ldoem::e2e {

// How ldoem-scan reaches the emulated scanner.
enum class Route {
  can,      // --device can:vcan0 (needs vcan0: UML)
  tcp,      // --device tcp:127.0.0.1:PORT
  hub_can,  // --hub: ldoem-hub with `scanner: can:vcan0`
  hub_tcp,  // --hub: ldoem-hub with `scanner: tcp:127.0.0.1:PORT`
  kernel_isotp,  // --device can:isotp:vcan0: the kernel's CAN_ISOTP (the gpio UML kernel only)
};
const char* to_string(Route route);

struct ScanRun {
  bool started = false;    // daemon (and hub) came up
  std::string failure;     // why not, with the children's stderr
  int exit_status = -1;    // ldoem-scan's
  std::string scan_stdout;  // the --fit line
  std::string scan_stderr;
  std::string ply_path;
  std::string ply_bytes;
  double wall_s = 0.0;     // ldoem-scan alone
};

struct ScanSettings {
  // The daemon's clock: --virtual-time (deterministic, fast) or --time-scale X.
  std::vector<std::string> clock_args{"--virtual-time"};
  std::vector<std::string> extra_scan_args;
  std::vector<std::string> extra_daemon_args;  // e.g. --record FILE
  // Serve the scan from `ldoem-emud --replay` of this capture instead of a scene (docs/replay.md).
  std::optional<std::string> replay_capture;
  std::vector<std::string> replay_args{"--virtual-time"};  // the recorded delays jumped over (D7)
  // A scene with a `scanners:` list instead of scenes/corridor.yaml (issue 15): the daemon takes
  // every endpoint from it (no --tcp, --lpt); its first scanner is scanned, over TCP, and must
  // have its LPT at the path the scan uses (lpt_path(dir, name)).
  std::optional<std::string> scanners_scene;
};

// Where scan_corridor puts (and expects) the scanned device's LPT pty for run `name`.
std::string lpt_path(const TempDir& dir, const std::string& name);

// The port in ldoem-hub's "listening on HOST:PORT" line, or empty.
std::string hub_port(const ChildProcess& hub);

// tshark with tools/wireshark/*.lua on a capture (tests/wireshark/check_dissector.py): every
// telegram ldoem's reader finds must decode, profile point counts included, nothing malformed.
// Returns the checker's output; `ok` tells whether it passed.
std::string check_capture_with_tshark(const TempDir& dir, const std::string& capture, bool& ok);

// Runs one whole scan in `dir` (files named after `name`); children are stopped before it returns.
ScanRun scan_corridor(const TempDir& dir, const std::string& name, Route route, const ScanSettings& settings = {});

// The numbers the acceptance is about (true values: 195 mm, 0.998 m, 4.180 m).
struct CorridorFit {
  double cylinder_diameter_m = 0.0;
  double cylinder_length_m = 0.0;
  double wall_distance_m = 0.0;
  std::size_t point_count = 0;
};

// ldoem-scan --fit's line: "wall distance 4.1800 m (..); cylinder diameter 0.1950 m, length 0.9958 m (..)".
std::optional<CorridorFit> parse_tool_fit(const std::string& scan_stdout);

// Our own fit of the PLY, independent of ldoem-scan's: the floor and the wall are removed as
// planes (the wall is the one facing +x), the cylinder is fitted near its known place with a
// vertical axis hint. Nothing when the file does not read or a fit fails (`why` says which).
std::optional<CorridorFit> fit_corridor_ply(const std::string& ply_path, std::string& why);

}  // namespace ldoem::e2e
