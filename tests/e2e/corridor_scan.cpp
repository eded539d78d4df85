#include "corridor_scan.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/cloud/fitting.hpp"

namespace ldoem::e2e {
namespace {

using namespace std::chrono_literals;

// Start-up in UML under load is the slow case: loading the scene and building the BVH.
constexpr auto kReadyLimit = 60s;
// A virtual-time scan takes ~3 s on the host; real time ~40 s. Generous, never a hang.
constexpr auto kScanLimit = 300s;
// Every daemon also stops by itself (--timeout) should the test process die.
const std::string kDaemonSelfStopS = "900";

// The paper's settings (Koceski & Koceska 2013): 20 deg x 21.6 deg at 0.25 deg x 0.18 deg, 10 Hz.
const std::vector<std::string> kPaperSettings{"--horizontal-apex", "20",   "--horizontal-resolution", "0.25",
                                              "--vertical-apex",   "21.6", "--vertical-resolution",   "0.18",
                                              "--speed",           "10"};

// Where the cylinder stands in the scanner's pivot frame (docs/scenes.md: axis at x = 2.9 m, y = 0).
constexpr double kCylinderAxisX = 2.9;
constexpr double kCylinderAxisY = 0.0;
constexpr double kCylinderSearchRadius = 0.3;  // the nearest box corner is further away

bool uses_hub(Route route) { return route == Route::hub_can || route == Route::hub_tcp; }
bool uses_can(Route route) { return route == Route::can || route == Route::hub_can || route == Route::kernel_isotp; }

std::string tcp_address(const ChildProcess& daemon) {
  std::istringstream lines(daemon.stdout_text());
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("tcp ", 0) == 0) return line.substr(4);
  }
  return {};
}

// std::regex is avoided here: g++ 12 raises -Wmaybe-uninitialized inside it under ASan at -O1.

}  // namespace

std::string lpt_path(const TempDir& dir, const std::string& name) { return dir.path(name + "-lpt"); }

std::string hub_port(const ChildProcess& hub) {
  const std::string text = hub.stderr_text();
  const std::size_t start = text.find("listening on ");
  if (start == std::string::npos) return {};
  const std::size_t host_end = text.find_first_of(" \n", start + 13);
  const std::size_t colon = text.rfind(':', host_end == std::string::npos ? text.size() : host_end);
  if (colon == std::string::npos || colon < start) return {};
  std::size_t digits = colon + 1;
  while (digits < text.size() && text[digits] >= '0' && text[digits] <= '9') ++digits;
  return text.substr(colon + 1, digits - colon - 1);
}


const char* to_string(Route route) {
  switch (route) {
    case Route::can: return "can";
    case Route::tcp: return "tcp";
    case Route::hub_can: return "hub->can";
    case Route::hub_tcp: return "hub->tcp";
    case Route::kernel_isotp: return "can:isotp";
  }
  return "?";
}

ScanRun scan_corridor(const TempDir& dir, const std::string& name, Route route, const ScanSettings& settings) {
  ScanRun run;
  const std::string lpt = lpt_path(dir, name);
  std::vector<std::string> daemon_args{"--scene", std::string(LDOEM_SOURCE_DIR) + "/scenes/corridor.yaml",
                                       "--lpt",   "lpt:pty:" + lpt,
                                       "--no-flash", "--timeout", kDaemonSelfStopS};
  if (settings.scanners_scene) {
    daemon_args = {"--scene", *settings.scanners_scene, "--no-flash", "--timeout", kDaemonSelfStopS, "--no-can"};
  } else if (uses_can(route)) {
    daemon_args.insert(daemon_args.end(), {"--can", "can:vcan0"});
  } else {
    daemon_args.insert(daemon_args.end(), {"--no-can", "--tcp", "tcp:127.0.0.1:0"});
  }
  daemon_args.insert(daemon_args.end(), settings.clock_args.begin(), settings.clock_args.end());
  daemon_args.insert(daemon_args.end(), settings.extra_daemon_args.begin(), settings.extra_daemon_args.end());
  std::string program = LDOEM_EMUD_PATH;
  if (settings.replay_capture) {
    // The same daemon and endpoints, a recorded device behind them (ldoem-emud --replay).
    daemon_args = {"--replay", *settings.replay_capture, "--lpt", "lpt:pty:" + lpt};
    if (uses_can(route)) {
      daemon_args.insert(daemon_args.end(), {"--can", "can:vcan0"});
    } else {
      daemon_args.insert(daemon_args.end(), {"--tcp", "tcp:127.0.0.1:0"});
    }
    daemon_args.insert(daemon_args.end(), settings.replay_args.begin(), settings.replay_args.end());
  }
  auto daemon = ChildProcess::start(program, daemon_args, dir.path(name + "-daemon"));
  if (!daemon || !daemon->wait_for_line("ready", false, kReadyLimit)) {
    run.failure = program + " not ready: " + (daemon ? daemon->stderr_text() : std::string("spawn failed"));
    return run;
  }
  const std::string scanner = route == Route::kernel_isotp ? "can:isotp:vcan0"
                              : uses_can(route)              ? "can:vcan0"
                                                             : "tcp:" + tcp_address(*daemon);

  std::optional<ChildProcess> hub;
  std::vector<std::string> device_args;
  if (uses_hub(route)) {
    const std::string config = dir.write(name + "-hub.yaml", "devices:\n"
                                                             "  - name: corridor\n"
                                                             "    scanner: " + scanner + "\n"
                                                             "    lpt: lpt:pty:" + lpt + "\n");
    if (auto started = ChildProcess::start(LDOEM_HUB_PATH, {"--config", config, "--listen", "127.0.0.1:0"},
                                           dir.path(name + "-hub"))) {
      hub.emplace(std::move(*started));
    }
    if (!hub || !hub->wait_for_line("listening on", true, kReadyLimit) || hub_port(*hub).empty()) {
      run.failure = "ldoem-hub not listening: " + (hub ? hub->stderr_text() : std::string("spawn failed"));
      return run;
    }
    device_args = {"--hub", "127.0.0.1:" + hub_port(*hub), "--hub-device", "corridor"};
  } else {
    device_args = {"--device", scanner, "--lpt", "lpt:pty:" + lpt};
  }
  run.started = true;

  run.ply_path = dir.path(name + ".ply");
  std::vector<std::string> scan_args = device_args;
  scan_args.insert(scan_args.end(), kPaperSettings.begin(), kPaperSettings.end());
  scan_args.insert(scan_args.end(), {"--out", run.ply_path, "--fit"});
  scan_args.insert(scan_args.end(), settings.extra_scan_args.begin(), settings.extra_scan_args.end());
  const auto started = std::chrono::steady_clock::now();
  auto scan = ChildProcess::start(LDOEM_SCAN_PATH, scan_args, dir.path(name + "-scan"));
  if (!scan) {
    run.failure = "ldoem-scan did not start";
    return run;
  }
  const std::optional<int> status = scan->wait(kScanLimit);
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  run.exit_status = status ? *status : scan->stop();
  run.scan_stdout = scan->stdout_text();
  run.scan_stderr = scan->stderr_text();
  run.ply_bytes = read_file(run.ply_path);
  if (hub) hub->stop();
  daemon->stop();
  if (run.exit_status != 0) {
    run.failure = "ldoem-scan exit " + std::to_string(run.exit_status) + ": " + run.scan_stderr +
                  "\nldoem-emud: " + daemon->stderr_text() + (hub ? "\nldoem-hub: " + hub->stderr_text() : "");
  }
  return run;
}

std::optional<CorridorFit> parse_tool_fit(const std::string& scan_stdout) {
  const std::size_t start = scan_stdout.find("wall distance ");
  if (start == std::string::npos) return std::nullopt;
  CorridorFit fit;
  int points = 0;
  int consumed = 0;
  if (std::sscanf(scan_stdout.c_str() + start, "wall distance %lf m (%d points); cylinder diameter %lf m, length %lf m%n",
                  &fit.wall_distance_m, &points, &fit.cylinder_diameter_m, &fit.cylinder_length_m, &consumed) != 4 ||
      consumed == 0) {
    return std::nullopt;
  }
  return fit;
}

std::optional<CorridorFit> fit_corridor_ply(const std::string& ply_path, std::string& why) {
  auto cloud = cloud::read_cloud_file(ply_path);
  if (!cloud) {
    why = "cannot read " + ply_path;
    return std::nullopt;
  }
  CorridorFit result;
  result.point_count = cloud->size();
  std::vector<Eigen::Vector3d> remaining = cloud::finite_positions(*cloud);

  // The two large planes: the floor (normal z) and the wall (normal x), in whichever order.
  std::optional<double> wall_distance;
  for (int plane_index = 0; plane_index < 2; ++plane_index) {
    auto plane = cloud::fit_plane_ransac(remaining);
    if (!plane) {
      why = "plane " + std::to_string(plane_index) + ": " + std::string(cloud::to_string(plane.error()));
      return std::nullopt;
    }
    if (std::abs(plane->normal.x()) > 0.9) wall_distance = plane->offset_m;
    std::vector<Eigen::Vector3d> rest;
    std::size_t next_inlier = 0;
    for (std::size_t i = 0; i < remaining.size(); ++i) {
      if (next_inlier < plane->inliers.size() && plane->inliers[next_inlier] == i) {
        ++next_inlier;
      } else {
        rest.push_back(remaining[i]);
      }
    }
    remaining = std::move(rest);
  }
  if (!wall_distance) {
    why = "no plane facing +x among the two largest";
    return std::nullopt;
  }
  result.wall_distance_m = *wall_distance;

  std::vector<Eigen::Vector3d> near_cylinder;
  for (const Eigen::Vector3d& point : remaining) {
    if (std::hypot(point.x() - kCylinderAxisX, point.y() - kCylinderAxisY) <= kCylinderSearchRadius) {
      near_cylinder.push_back(point);
    }
  }
  cloud::CylinderRansacOptions options;
  options.axis_hint = cloud::AxisHint{Eigen::Vector3d::UnitZ(), 0.1};
  auto cylinder = cloud::fit_cylinder_ransac(near_cylinder, options);
  if (!cylinder) {
    why = "cylinder: " + std::string(cloud::to_string(cylinder.error()));
    return std::nullopt;
  }
  result.cylinder_diameter_m = 2.0 * cylinder->radius_m;
  result.cylinder_length_m = cylinder->length_m;
  return result;
}

std::string check_capture_with_tshark(const TempDir& dir, const std::string& capture, bool& ok) {
  ok = false;
  const std::string expect = capture + ".expect.json";
  auto expectations = ChildProcess::start(LDOEM_CAPTURE_EXPECTATIONS_PATH, {capture}, dir.path("expectations"));
  if (!expectations || expectations->wait(std::chrono::seconds(60)) != std::optional<int>(0)) {
    return "ldoem_capture_expectations failed: " + (expectations ? expectations->stderr_text() : std::string("spawn"));
  }
  dir.write(capture.substr(capture.rfind('/') + 1) + ".expect.json", expectations->stdout_text());
  auto checker = ChildProcess::start(
      "/usr/bin/python3",
      {std::string(LDOEM_SOURCE_DIR) + "/tests/wireshark/check_dissector.py", "--tshark", LDOEM_TSHARK_PATH,
       "--lua-dir", std::string(LDOEM_SOURCE_DIR) + "/tools/wireshark", "--capture", capture, "--expect", expect},
      dir.path("check-dissector"));
  if (!checker) return "check_dissector.py did not start";
  const auto status = checker->wait(std::chrono::seconds(300));
  ok = status == std::optional<int>(0);
  return checker->stdout_text() + checker->stderr_text();
}

}  // namespace ldoem::e2e
