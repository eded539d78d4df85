// The device as the hub's back-end handlers and ldoem-scan see it: the paper's generic
// interface (INITIALIZE, ROTATE, MEASURE, IDLE, GET2DPROFILE, MOVEMOTOR, STATUS) as one small
// abstract class (design.md convention 2). ScannerDevice drives a scanner and its tilt stepper
// through libldoem; HubDevice forwards to a hub over TCP; tests implement fakes. A caller
// cannot tell which one it holds.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ldoem/driver/error.hpp"
#include "ldoem/driver/scanner.hpp"
#include "ldoem/protocol/lpt.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/status.hpp"

namespace ldoem::driver {

using protocol::StatusBlock;
using protocol::StepMode;
using protocol::TiltDirection;

// What INITIALIZE may configure besides connecting. Every field is optional: an empty request
// only connects, normalises the state to IDLE and reads the identification.
struct InitializeRequest {
  std::optional<std::uint16_t> motor_speed_hz;    // global config MOTORSPEED (spec 3.4)
  std::optional<std::uint16_t> angle_step_ticks;  // global config ANGLESTEP, 1/16 deg
  std::vector<SectorDefinition> sectors;  // written temporarily (not to flash) if any
  bool operator==(const InitializeRequest&) const = default;
};

struct DeviceInfo {
  StatusBlock status;  // after INITIALIZE
  std::vector<IdentificationEntry> identification;
  bool operator==(const DeviceInfo&) const = default;
};

// The commanded tilt position: the stepper has no encoder, so this is what was commanded (D8).
struct TiltPosition {
  std::int64_t half_steps = 0;  // positive: tilt angle grew (D8 DATA0 = 1)
  double tilt_deg() const { return static_cast<double>(half_steps) * protocol::kOutputShaftHalfStepDeg; }
  bool operator==(const TiltPosition&) const = default;
};

// MOVEMOTOR's limits (docs/hub.md): a request outside them is refused before anything moves,
// so no request can put a device worker to sleep for longer than kMaxMoveSteps / kMinStepRateHz.
inline constexpr std::uint32_t kMaxMoveSteps = 20000;  // 900 deg of tilt in full steps
inline constexpr double kMinStepRateHz = 1.0;
inline constexpr double kMaxStepRateHz = 20000.0;

struct MotorMove {
  std::uint32_t steps = 0;
  TiltDirection direction = TiltDirection::increasing;
  StepMode mode = StepMode::full_step;
  std::optional<double> step_rate_hz;  // empty: the device's default
  bool operator==(const MotorMove&) const = default;
};

// One profile and the tilt it was taken at.
struct ProfileSample {
  protocol::Profile profile;
  TiltPosition tilt;
  bool operator==(const ProfileSample&) const = default;
};

class Device {
 public:
  virtual ~Device() = default;

  // Connects (opening the transport if needed), reads the status, brings the scanner to IDLE
  // (DO_RESET halt-to-idle when it is not), reads the identification, applies `request`.
  virtual Expected<DeviceInfo, DriverError> initialize(const InitializeRequest& request) = 0;
  // TRANS_ROTATE (0 = the configured speed); leaves MEASURE as well (spec 5).
  virtual Expected<StatusBlock, DriverError> rotate(std::uint16_t frequency_hz) = 0;
  virtual Expected<StatusBlock, DriverError> measure() = 0;
  // TRANS_IDLE, passing through ROTATE when the scanner measures (spec 5: no direct jump).
  virtual Expected<StatusBlock, DriverError> idle() = 0;
  // One fresh profile (GET_PROFILE with a count of 1) in the device's format.
  virtual Expected<ProfileSample, DriverError> get_profile(std::chrono::milliseconds timeout) = 0;
  // Steps the tilt motor; returns the commanded position after the move.
  virtual Expected<TiltPosition, DriverError> move_motor(const MotorMove& move) = 0;
  virtual Expected<StatusBlock, DriverError> status() = 0;
  // Thread-safe: makes a move in progress stop at its next step with ErrorKind::interrupted,
  // and every later one fail the same way. The hub calls it when it shuts down.
  virtual void cancel() {}
};

}  // namespace ldoem::driver
