// The hub serves the driver's device interface (ldoem/driver/device.hpp): its line protocol,
// back-end handlers and client speak that vocabulary, so the hub names it as its own.
#pragma once

#include "ldoem/driver/device.hpp"

namespace ldoem::hub {

using driver::Device;
using driver::DeviceInfo;
using driver::DriverError;
using driver::ErrorKind;
using driver::Expected;
using driver::InitializeRequest;
using driver::kMaxMoveSteps;
using driver::kMaxStepRateHz;
using driver::kMinStepRateHz;
using driver::MotorMove;
using driver::ProfileSample;
using driver::TiltPosition;
using protocol::StatusBlock;
using protocol::StepMode;
using protocol::TiltDirection;

}  // namespace ldoem::hub
