// A Device made of a scanner reached through libldoem (any TelegramTransport) and, optionally, the
// tilt stepper on an LPT port (D8). Nothing is opened at construction: the transport opens at
// INITIALIZE (and at the next INITIALIZE after the connection was lost, through
// Scanner::reconnect with options.scanner.reconnect's bounded attempts), the LPT port at
// the first MOVEMOTOR, so a hub starts even when a device is not there yet. It lives in libldoem,
// not in the hub: ldoem-scan drives a scanner directly through it without linking the hub.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "ldoem/driver/device.hpp"
#include "ldoem/driver/endpoint.hpp"
#include "ldoem/driver/lpt_port.hpp"
#include "ldoem/driver/scanner.hpp"
#include "ldoem/driver/tilt_stepper.hpp"
#include "ldoem/driver/transport.hpp"

namespace ldoem::driver {

// Defaults of MOVEMOTOR when the request leaves them out.
struct StepperDefaults {
  double step_rate_hz = 200.0;
  // A MOVEMOTOR whose steps / rate would take longer is refused (invalid_argument).
  std::chrono::milliseconds max_move_duration{120000};
  bool operator==(const StepperDefaults&) const = default;
};

struct ScannerDeviceOptions {
  ScannerOptions scanner;
  StepperDefaults stepper;
  // GET2DPROFILE's format: range and echo (S1's 0x3DFF, spec 3.5).
  std::uint16_t profile_format = protocol::kFormatRangeEcho;
};

using TransportFactory = TransportOpener;  // the same opener Scanner::reconnect uses
using LptFactory = std::function<Expected<std::unique_ptr<LptPort>, DriverError>()>;

class ScannerDevice final : public Device {
 public:
  // `open_lpt` empty: the device has no tilt stepper (MOVEMOTOR with steps > 0 is unsupported).
  ScannerDevice(std::string name, TransportFactory open_transport, LptFactory open_lpt,
                std::unique_ptr<Sleeper> sleeper, ScannerDeviceOptions options = {});
  // The factories open_transport(scanner) and open_lpt_port(lpt); a MonotonicSleeper.
  static std::unique_ptr<ScannerDevice> from_endpoints(std::string name, const Endpoint& scanner,
                                                       const std::optional<Endpoint>& lpt,
                                                       ScannerDeviceOptions options = {});
  ~ScannerDevice() override;

  Expected<DeviceInfo, DriverError> initialize(const InitializeRequest& request) override;
  Expected<StatusBlock, DriverError> rotate(std::uint16_t frequency_hz) override;
  Expected<StatusBlock, DriverError> measure() override;
  Expected<StatusBlock, DriverError> idle() override;
  Expected<ProfileSample, DriverError> get_profile(std::chrono::milliseconds timeout) override;
  Expected<TiltPosition, DriverError> move_motor(const MotorMove& move) override;
  Expected<StatusBlock, DriverError> status() override;
  // Interrupts the sleeper: a move in progress stops at its next step.
  void cancel() override;

  const std::string& name() const { return name_; }

 private:
  Expected<Scanner*, DriverError> connected_scanner(const char* operation);
  Expected<DeviceInfo, DriverError> configure(Scanner& scanner, const InitializeRequest& request);
  // Closes a scanner whose connection is gone, so that the next INITIALIZE reconnects it.
  template <class T>
  Expected<T, DriverError> watch(Expected<T, DriverError> result);

  std::string name_;
  TransportFactory open_transport_;
  LptFactory open_lpt_;
  std::unique_ptr<Sleeper> sleeper_;
  ScannerDeviceOptions options_;
  std::unique_ptr<Scanner> scanner_;
  std::unique_ptr<LptPort> lpt_port_;
  std::unique_ptr<TiltStepper> stepper_;
  std::int64_t position_half_steps_ = 0;  // kept across LPT re-opens
};

}  // namespace ldoem::driver
