// The paper's acquisition sequence over any Device (direct or through the hub):
//   INITIALIZE (connect, status, identification, reset to IDLE, speed/step, sector table)
//   MOVEMOTOR to the low vertical apex, ROTATE, MEASURE,
//   per layer: GET2DPROFILE, then MOVEMOTOR one layer step (not after the last layer),
//   IDLE, MOVEMOTOR home (tilt 0).
// A failure or a stop request after INITIALIZE still tries IDLE and the move home.
//
// Faults (D11, docs/faults.md "Host side"): a step that fails retryably (a timeout, a corrupted
// reply, a lost connection) is tried again, at most `retries` more times. Before that the
// device is asked for its status: a fault there (a motor nibble, ERROR) is final and named; a
// lost connection, or a device that left MEASURE by itself (a power cycle, a spontaneous reset),
// is measuring again first (INITIALIZE, which reconnects and re-applies the configuration,
// ROTATE, MEASURE). The tilt is not moved by a restart, so the layer is taken where it belongs.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "ldoem/cloud/point_cloud.hpp"
#include "ldoem/driver/device.hpp"
#include "ldoem/scan/scan_grid.hpp"
#include "ldoem/scan/profile_points.hpp"
#include "ldoem/scan/scan_plan.hpp"

namespace ldoem::scan {

struct AcquisitionPlan {
  SectorPlan sectors;
  LayerPlan layers;
  std::uint16_t motor_speed_hz = 10;
  std::optional<double> step_rate_hz;  // empty: the device's default
  Vector3 optical_offset_m;
  std::chrono::milliseconds profile_timeout{5000};
  std::uint32_t retries = 3;  // further attempts per step after a retryable fault
  std::chrono::milliseconds retry_pause{200};  // times the attempt number, before each retry
};

inline constexpr std::uint32_t kDefaultRetries = 3;

struct AcquisitionHooks {
  // After each layer: (layers done, layer count).
  std::function<void(std::uint32_t, std::uint32_t)> on_layer;
  // Polled between steps; true ends the scan (with the clean-up) as `stopped`.
  std::function<bool()> should_stop;
  // Before each retry: (stage, the fault, attempt 1..retries, retries).
  std::function<void(const std::string&, const driver::DriverError&, std::uint32_t, std::uint32_t)> on_retry;
  // How to wait retry_pause; empty: std::this_thread::sleep_for.
  std::function<void(std::chrono::milliseconds)> sleep;
};

struct Scan {
  // Organised as ScanGrid lays it out (scan_grid.hpp): NaN points where a beam had no echo.
  cloud::PointCloud cloud{kScanChannels};
  driver::DeviceInfo device;
  std::uint32_t layers_done = 0;
  std::uint32_t retries_used = 0;  // over the whole scan
  std::uint32_t restarts = 0;      // INITIALIZE, ROTATE, MEASURE again after a lost connection or reset
};

enum class AcquisitionFailure : std::uint8_t { device_error, stopped };

struct AcquisitionError {
  AcquisitionFailure failure = AcquisitionFailure::device_error;
  std::string stage;                          // "INITIALIZE", "GET2DPROFILE layer 12", ...
  std::optional<driver::DriverError> error;      // device_error
  std::optional<driver::DriverError> cleanup_error;  // the first failure of IDLE / move home, if any
};

std::string describe(const AcquisitionError& error);

// The point cloud in the pivot frame; ring = layer, image position = (layer, beam).
base::Expected<Scan, AcquisitionError> acquire(driver::Device& device, const AcquisitionPlan& plan,
                                                   const AcquisitionHooks& hooks = {});

}  // namespace ldoem::scan
