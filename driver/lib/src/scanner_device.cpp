#include "ldoem/driver/scanner_device.hpp"

#include <utility>

#include "ldoem/protocol/messages.hpp"

namespace ldoem::driver {
namespace {

bool is_measuring(const StatusBlock& status) { return status.status.sensor == protocol::SensorMode::measure; }

}  // namespace

ScannerDevice::ScannerDevice(std::string name, TransportFactory open_transport, LptFactory open_lpt,
                             std::unique_ptr<Sleeper> sleeper, ScannerDeviceOptions options)
    : name_(std::move(name)),
      open_transport_(std::move(open_transport)),
      open_lpt_(std::move(open_lpt)),
      sleeper_(std::move(sleeper)),
      options_(std::move(options)) {
  options_.scanner.reopen = open_transport_;  // Scanner::reconnect() after a lost connection
}

ScannerDevice::~ScannerDevice() {
  if (scanner_) {
    scanner_->close();
  }
}

std::unique_ptr<ScannerDevice> ScannerDevice::from_endpoints(std::string name, const Endpoint& scanner,
                                                             const std::optional<Endpoint>& lpt,
                                                             ScannerDeviceOptions options) {
  TransportFactory transport = [scanner] { return driver::open_transport(scanner); };
  LptFactory port;
  if (lpt) {
    port = [endpoint = *lpt] { return driver::open_lpt_port(endpoint); };
  }
  return std::make_unique<ScannerDevice>(std::move(name), std::move(transport), std::move(port),
                                         std::make_unique<MonotonicSleeper>(), std::move(options));
}

template <class T>
Expected<T, DriverError> ScannerDevice::watch(Expected<T, DriverError> result) {
  if (!result && result.error().kind == ErrorKind::connection_closed && scanner_) {
    scanner_->close();  // the next INITIALIZE reconnects (bounded attempts, ScannerOptions)
  }
  return result;
}

Expected<Scanner*, DriverError> ScannerDevice::connected_scanner(const char* operation) {
  if (!scanner_ || scanner_->state() == LifecycleState::closed ||
      scanner_->state() == LifecycleState::unconfigured) {
    return fail(make_error(ErrorKind::wrong_state, operation, name_, "INITIALIZE the device first"));
  }
  return scanner_.get();
}

Expected<DeviceInfo, DriverError> ScannerDevice::initialize(const InitializeRequest& request) {
  if (!scanner_) {
    auto transport = open_transport_();
    if (!transport) {
      return fail(transport.error());
    }
    scanner_ = std::make_unique<Scanner>(std::move(transport.value()), options_.scanner);
  } else if (scanner_->state() == LifecycleState::closed) {
    // The connection was lost (a reset, a power cycle): try again, a bounded number of times.
    if (auto reconnected = scanner_->reconnect(); !reconnected) {
      return fail(reconnected.error());
    }
  }
  return watch(configure(*scanner_, request));
}

Expected<DeviceInfo, DriverError> ScannerDevice::configure(Scanner& scanner, const InitializeRequest& request) {
  auto connected = scanner.connect();
  if (!connected) {
    return fail(connected.error());
  }
  if (scanner.state() == LifecycleState::active) {
    if (auto cancelled = scanner.cancel_profile(); !cancelled) {
      return fail(cancelled.error());
    }
  }
  // Configuration is only accepted in IDLE (D2); halt-to-idle works from every state (spec 3.3).
  if (connected->status.status.sensor != protocol::SensorMode::idle) {
    if (auto reset = scanner.do_reset(protocol::reset_level::kHaltToIdle); !reset) {
      return fail(reset.error());
    }
  }
  auto identification = scanner.identify_all();
  if (!identification) {
    return fail(identification.error());
  }
  if (request.motor_speed_hz || request.angle_step_ticks) {
    auto global = scanner.get_global_config();
    if (!global) {
      return fail(global.error());
    }
    protocol::GlobalConfig config = global.value();
    config.motor_speed_hz = request.motor_speed_hz.value_or(config.motor_speed_hz);
    config.angle_step_ticks = request.angle_step_ticks.value_or(config.angle_step_ticks);
    config.trailing_zero_word = false;
    if (auto written = scanner.set_config(config); !written) {
      return fail(written.error());
    }
  }
  if (!request.sectors.empty()) {
    if (auto written = scanner.write_sector_table(request.sectors, false); !written) {
      return fail(written.error());
    }
  }
  auto status = scanner.get_status();
  if (!status) {
    return fail(status.error());
  }
  return DeviceInfo{status->status, std::move(identification.value())};
}

Expected<StatusBlock, DriverError> ScannerDevice::rotate(std::uint16_t frequency_hz) {
  auto scanner = connected_scanner("ROTATE");
  if (!scanner) {
    return fail(scanner.error());
  }
  return watch((*scanner)->trans_rotate(frequency_hz));
}

Expected<StatusBlock, DriverError> ScannerDevice::measure() {
  auto scanner = connected_scanner("MEASURE");
  if (!scanner) {
    return fail(scanner.error());
  }
  return watch((*scanner)->trans_measure());
}

Expected<StatusBlock, DriverError> ScannerDevice::idle() {
  auto scanner = connected_scanner("IDLE");
  if (!scanner) {
    return fail(scanner.error());
  }
  auto current = watch((*scanner)->get_status());
  if (!current) {
    return fail(current.error());
  }
  // Spec 5: MEASURE -> IDLE must pass through ROTATE (D2 refuses the direct jump).
  if (is_measuring(current->status)) {
    if (auto rotated = watch((*scanner)->trans_rotate()); !rotated) {
      return fail(rotated.error());
    }
  }
  return watch((*scanner)->trans_idle());
}

Expected<ProfileSample, DriverError> ScannerDevice::get_profile(std::chrono::milliseconds timeout) {
  auto scanner = connected_scanner("GET2DPROFILE");
  if (!scanner) {
    return fail(scanner.error());
  }
  Scanner& device = **scanner;
  if (auto requested = watch(device.get_profile(1, options_.profile_format)); !requested) {
    return fail(requested.error());
  }
  auto profile = watch(device.next_profile(Clock::now() + timeout));
  if (!profile) {
    // A stream left running would answer the next request with a profile (D10).
    if (scanner_ && scanner_->state() == LifecycleState::active) {
      (void)scanner_->cancel_profile();
    }
    return fail(profile.error());
  }
  return ProfileSample{std::move(profile.value()), TiltPosition{position_half_steps_}};
}

Expected<TiltPosition, DriverError> ScannerDevice::move_motor(const MotorMove& move) {
  if (move.steps == 0) {
    return TiltPosition{position_half_steps_};
  }
  if (!open_lpt_) {
    return fail(make_error(ErrorKind::unsupported, "MOVEMOTOR", name_, "the device has no LPT endpoint"));
  }
  if (!stepper_) {
    auto port = open_lpt_();
    if (!port) {
      return fail(port.error());
    }
    lpt_port_ = std::move(port.value());
    stepper_ = std::make_unique<TiltStepper>(*lpt_port_, *sleeper_);
    stepper_->set_position_half_steps(position_half_steps_);
  }
  const double rate_hz = move.step_rate_hz.value_or(options_.stepper.step_rate_hz);
  const double seconds = static_cast<double>(move.steps) / rate_hz;
  const double limit_s = std::chrono::duration<double>(options_.stepper.max_move_duration).count();
  if (!(seconds <= limit_s)) {
    return fail(make_error(ErrorKind::invalid_argument, "MOVEMOTOR", name_,
                           std::to_string(move.steps) + " steps at " + std::to_string(rate_hz) +
                               " Hz would take longer than the limit of " + std::to_string(limit_s) + " s"));
  }
  const Status moved = stepper_->move(move.steps, move.direction, move.mode, rate_hz);
  position_half_steps_ = stepper_->position_half_steps();
  if (!moved && moved.error().kind != ErrorKind::invalid_argument) {
    // Re-open the port on the next move; the position counts the steps actually pulsed.
    stepper_.reset();
    lpt_port_.reset();
  }
  if (!moved) {
    return fail(moved.error());
  }
  return TiltPosition{position_half_steps_};
}

void ScannerDevice::cancel() { sleeper_->interrupt(); }

Expected<StatusBlock, DriverError> ScannerDevice::status() {
  auto scanner = connected_scanner("STATUS");
  if (!scanner) {
    return fail(scanner.error());
  }
  auto reply = watch((*scanner)->get_status());
  if (!reply) {
    return fail(reply.error());
  }
  return reply->status;
}

}  // namespace ldoem::driver
