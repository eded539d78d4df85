// The paper's acquisition sequence over any Device (direct or through the hub):
//   INITIALIZE (connect, status, identification, reset to IDLE, speed/step, sector table)
//   MOVEMOTOR to the low vertical apex, ROTATE, MEASURE,
//   per layer: GET2DPROFILE, then MOVEMOTOR one layer step (not after the last layer),
//   IDLE, MOVEMOTOR home (tilt 0).
// A failure or a stop request after INITIALIZE still tries IDLE and the move home.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "ldoem/cloud/point_cloud.hpp"
#include "ldoem/driver/device.hpp"
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
};

struct AcquisitionHooks {
  // After each layer: (layers done, layer count).
  std::function<void(std::uint32_t, std::uint32_t)> on_layer;
  // Polled between steps; true ends the scan (with the clean-up) as `stopped`.
  std::function<bool()> should_stop;
};

struct Scan {
  cloud::PointCloud cloud{cloud::CloudChannels{true, true, true}};  // echo, ring = layer, image position
  driver::DeviceInfo device;
  std::uint32_t layers_done = 0;
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
protocol::Expected<Scan, AcquisitionError> acquire(driver::Device& device, const AcquisitionPlan& plan,
                                                   const AcquisitionHooks& hooks = {});

}  // namespace ldoem::scan
