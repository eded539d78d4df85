#include "ldoem/scan/acquisition.hpp"

#include <thread>
#include <utility>

namespace ldoem::scan {
namespace {

using driver::MotorMove;
using driver::TiltDirection;
using base::Unexpected;

MotorMove move_by(std::int64_t steps, const AcquisitionPlan& plan) {
  MotorMove move;
  move.steps = static_cast<std::uint32_t>(steps < 0 ? -steps : steps);
  move.direction = steps < 0 ? TiltDirection::decreasing : TiltDirection::increasing;
  move.mode = plan.layers.mode;
  move.step_rate_hz = plan.step_rate_hz;
  return move;
}

class Run {
 public:
  Run(driver::Device& device, const AcquisitionPlan& plan, const AcquisitionHooks& hooks)
      : device_(device), plan_(plan), hooks_(hooks) {}

  base::Expected<Scan, AcquisitionError> execute() {
    init_.motor_speed_hz = plan_.motor_speed_hz;
    init_.angle_step_ticks = plan_.sectors.angle_step_ticks;
    init_.sectors = plan_.sectors.sectors;
    auto info = with_retries("INITIALIZE", Phase::initializing, [this] { return device_.initialize(init_); });
    if (!info) {
      return Unexpected<AcquisitionError>({AcquisitionFailure::device_error, "INITIALIZE", info.error(), {}});
    }
    scan_.device = std::move(info.value());
    if (auto failed = measure_layers()) {
      failed->cleanup_error = clean_up(failed->error);
      return Unexpected<AcquisitionError>(std::move(*failed));
    }
    if (auto idle = device_.idle(); !idle) {
      return Unexpected<AcquisitionError>({AcquisitionFailure::device_error, "IDLE", idle.error(), clean_up()});
    }
    if (auto home = go_home(); !home) {
      return Unexpected<AcquisitionError>({AcquisitionFailure::device_error, "MOVEMOTOR home", home.error(), {}});
    }
    scan_.cloud = grid_.build();
    return std::move(scan_);
  }

 private:
  bool stop_requested() const { return hooks_.should_stop && hooks_.should_stop(); }

  std::optional<AcquisitionError> device_failure(std::string stage, const driver::DriverError& error) const {
    return AcquisitionError{AcquisitionFailure::device_error, std::move(stage), error, {}};
  }

  std::optional<AcquisitionError> stopped(std::string stage) const {
    return AcquisitionError{AcquisitionFailure::stopped, std::move(stage), {}, {}};
  }

  // What a failed step calls for, once the device has been asked for its status.
  struct Diagnosis {
    bool retry = false;
    bool restart = false;  // INITIALIZE, ROTATE, MEASURE before trying again
    driver::DriverError error;
  };

  // Where in the scan a step is: what a lost connection calls for differs.
  enum class Phase : std::uint8_t {
    initializing,  // INITIALIZE itself reconnects
    starting,      // ROTATE, MEASURE: INITIALIZE again first after a lost connection
    measuring,     // layers: also INITIALIZE again when the device left MEASURE by itself
  };

  Diagnosis diagnose(driver::DriverError error, Phase phase) {
    const bool initialized = phase != Phase::initializing;
    if (error.kind == driver::ErrorKind::device_fault) {
      return {false, false, std::move(error)};
    }
    if (error.kind == driver::ErrorKind::connection_closed) {
      return {true, initialized, std::move(error)};  // a reset or a power cycle: reconnect, configure again
    }
    // The status names a motor fault behind a timeout (a stalled head stops the stream, D11),
    // and shows a device that left MEASURE by itself (a spontaneous reset).
    auto status = device_.status();
    if (!status) {
      const auto kind = status.error().kind;
      const bool lost =
          initialized && (kind == driver::ErrorKind::connection_closed || kind == driver::ErrorKind::wrong_state);
      return {lost || driver::is_retryable(error), lost, std::move(error)};
    }
    if (auto fault = driver::device_fault_in(*status, "GET_STATUS", error.object)) {
      fault->detail += " after " + driver::describe(error);
      return {false, false, std::move(*fault)};
    }
    if (phase == Phase::measuring && status->status.sensor != protocol::SensorMode::measure) {
      return {true, true, std::move(error)};
    }
    return {driver::is_retryable(error), false, std::move(error)};
  }

  driver::Status restart_measuring() {
    ++scan_.restarts;
    if (auto info = device_.initialize(init_); !info) {
      return driver::fail(info.error());
    }
    if (auto rotating = device_.rotate(plan_.motor_speed_hz); !rotating) {
      return driver::fail(rotating.error());
    }
    if (auto measuring = device_.measure(); !measuring) {
      return driver::fail(measuring.error());
    }
    return driver::ok();
  }

  void pause(std::uint32_t attempt) const {
    const auto wait = plan_.retry_pause * attempt;
    if (hooks_.sleep) {
      hooks_.sleep(wait);
    } else {
      std::this_thread::sleep_for(wait);
    }
  }

  // Runs `step` until it succeeds, fails finally, or has been retried plan_.retries times.
  template <class Step>
  auto with_retries(const std::string& stage, Phase phase, Step step) -> decltype(step()) {
    bool restart = false;
    for (std::uint32_t attempt = 0;; ++attempt) {
      auto result = [&]() -> decltype(step()) {
        if (restart) {
          if (auto restarted = restart_measuring(); !restarted) {
            return driver::fail(restarted.error());
          }
          restart = false;
        }
        return step();
      }();
      if (result) {
        return result;
      }
      Diagnosis diagnosis = diagnose(result.error(), phase);
      if (!diagnosis.retry || attempt >= plan_.retries || stop_requested()) {
        return driver::fail(std::move(diagnosis.error));
      }
      restart = restart || diagnosis.restart;
      ++scan_.retries_used;
      if (hooks_.on_retry) {
        hooks_.on_retry(stage, diagnosis.error, attempt + 1, plan_.retries);
      }
      pause(attempt + 1);
    }
  }

  std::optional<AcquisitionError> measure_layers() {
    if (auto moved = move_to(plan_.layers.layer_half_steps(0)); !moved) {
      return device_failure("MOVEMOTOR to the low apex", moved.error());
    }
    if (stop_requested()) {
      return stopped("before ROTATE");
    }
    if (auto rotating = with_retries("ROTATE", Phase::starting, [this] { return device_.rotate(plan_.motor_speed_hz); });
        !rotating) {
      return device_failure("ROTATE", rotating.error());
    }
    if (auto measuring = with_retries("MEASURE", Phase::starting, [this] { return device_.measure(); }); !measuring) {
      return device_failure("MEASURE", measuring.error());
    }
    const std::uint32_t count = plan_.layers.layer_count;
    for (std::uint32_t layer = 0; layer < count; ++layer) {
      if (stop_requested()) {
        return stopped("layer " + std::to_string(layer));
      }
      const std::string stage = "GET2DPROFILE layer " + std::to_string(layer);
      auto sample = with_retries(stage, Phase::measuring, [this] { return device_.get_profile(plan_.profile_timeout); });
      if (!sample) {
        return device_failure(stage, sample.error());
      }
      add_layer(sample->profile, layer);
      scan_.layers_done = layer + 1;
      if (layer + 1 < count) {
        if (auto moved = move_to(plan_.layers.layer_half_steps(layer + 1)); !moved) {
          return device_failure("MOVEMOTOR layer " + std::to_string(layer + 1), moved.error());
        }
      }
      if (hooks_.on_layer) {
        hooks_.on_layer(layer + 1, count);
      }
    }
    return std::nullopt;
  }

  // The tilt is the commanded position of the layer (the stepper has no encoder, D8).
  void add_layer(const protocol::Profile& profile, std::uint32_t layer) {
    grid_.add_layer(layer, plan_.layers.layer_tilt_deg(layer), profile, plan_.optical_offset_m);
  }

  base::Expected<driver::TiltPosition, driver::DriverError> move_to(std::int64_t target_half_steps) {
    const std::int64_t delta_half = target_half_steps - position_half_steps_;
    const std::int64_t steps = delta_half / plan_.layers.half_steps_per_step();
    auto moved = device_.move_motor(move_by(steps, plan_));
    if (moved) {
      position_half_steps_ += steps * plan_.layers.half_steps_per_step();
    }
    return moved;
  }

  base::Expected<driver::TiltPosition, driver::DriverError> go_home() { return move_to(0); }

  std::optional<driver::DriverError> clean_up(const std::optional<driver::DriverError>& cause = std::nullopt) {
    std::optional<driver::DriverError> first;
    // A faulted device refuses TRANS_IDLE (reason 3, D11) and stays in ERROR until a DO_RESET
    // level 2 (the next INITIALIZE) once the cause is gone: only the tilt goes home.
    const bool faulted = cause && cause->kind == driver::ErrorKind::device_fault;
    if (!faulted) {
      if (auto idle = device_.idle(); !idle) {
        first = idle.error();
      }
    }
    if (auto home = go_home(); !home && !first) {
      first = home.error();
    }
    return first;
  }

  driver::Device& device_;
  driver::InitializeRequest init_;
  const AcquisitionPlan& plan_;
  const AcquisitionHooks& hooks_;
  Scan scan_;
  ScanGrid grid_;
  std::int64_t position_half_steps_ = 0;  // commanded, relative to where the scan started (level)
};

}  // namespace

std::string describe(const AcquisitionError& error) {
  std::string line = error.stage + ": ";
  line += error.failure == AcquisitionFailure::stopped ? "stopped by a signal"
                                                       : (error.error ? driver::describe(*error.error) : "failed");
  if (error.cleanup_error) {
    line += "; clean-up failed too: " + driver::describe(*error.cleanup_error);
  }
  return line;
}

base::Expected<Scan, AcquisitionError> acquire(driver::Device& device, const AcquisitionPlan& plan,
                                                   const AcquisitionHooks& hooks) {
  return Run(device, plan, hooks).execute();
}

}  // namespace ldoem::scan
