#include "ldoem/scan/acquisition.hpp"

#include <utility>

namespace ldoem::scan {
namespace {

using driver::MotorMove;
using driver::TiltDirection;
using protocol::Unexpected;

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

  protocol::Expected<Scan, AcquisitionError> execute() {
    driver::InitializeRequest init;
    init.motor_speed_hz = plan_.motor_speed_hz;
    init.angle_step_ticks = plan_.sectors.angle_step_ticks;
    init.sectors = plan_.sectors.sectors;
    auto info = device_.initialize(init);
    if (!info) {
      return Unexpected<AcquisitionError>({AcquisitionFailure::device_error, "INITIALIZE", info.error(), {}});
    }
    scan_.device = std::move(info.value());
    if (auto failed = measure_layers()) {
      failed->cleanup_error = clean_up();
      return Unexpected<AcquisitionError>(std::move(*failed));
    }
    if (auto idle = device_.idle(); !idle) {
      return Unexpected<AcquisitionError>({AcquisitionFailure::device_error, "IDLE", idle.error(), clean_up()});
    }
    if (auto home = go_home(); !home) {
      return Unexpected<AcquisitionError>({AcquisitionFailure::device_error, "MOVEMOTOR home", home.error(), {}});
    }
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

  std::optional<AcquisitionError> measure_layers() {
    if (auto moved = move_to(plan_.layers.layer_half_steps(0)); !moved) {
      return device_failure("MOVEMOTOR to the low apex", moved.error());
    }
    if (stop_requested()) {
      return stopped("before ROTATE");
    }
    if (auto rotating = device_.rotate(plan_.motor_speed_hz); !rotating) {
      return device_failure("ROTATE", rotating.error());
    }
    if (auto measuring = device_.measure(); !measuring) {
      return device_failure("MEASURE", measuring.error());
    }
    const std::uint32_t count = plan_.layers.layer_count;
    for (std::uint32_t layer = 0; layer < count; ++layer) {
      if (stop_requested()) {
        return stopped("layer " + std::to_string(layer));
      }
      auto sample = device_.get_profile(plan_.profile_timeout);
      if (!sample) {
        return device_failure("GET2DPROFILE layer " + std::to_string(layer), sample.error());
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
    const double tilt_deg = plan_.layers.layer_tilt_deg(layer);
    for (const BeamPoint& point : profile_to_points(profile, tilt_deg, plan_.optical_offset_m)) {
      cloud::PointRecord record;
      record.position = point.position;
      record.intensity = point.echo;
      record.ring = static_cast<std::uint16_t>(layer);
      record.image_position = {layer, point.beam};
      scan_.cloud.push_back(record);
    }
  }

  protocol::Expected<driver::TiltPosition, driver::DriverError> move_to(std::int64_t target_half_steps) {
    const std::int64_t delta_half = target_half_steps - position_half_steps_;
    const std::int64_t steps = delta_half / plan_.layers.half_steps_per_step();
    auto moved = device_.move_motor(move_by(steps, plan_));
    if (moved) {
      position_half_steps_ += steps * plan_.layers.half_steps_per_step();
    }
    return moved;
  }

  protocol::Expected<driver::TiltPosition, driver::DriverError> go_home() { return move_to(0); }

  std::optional<driver::DriverError> clean_up() {
    std::optional<driver::DriverError> first;
    if (auto idle = device_.idle(); !idle) {
      first = idle.error();
    }
    if (auto home = go_home(); !home && !first) {
      first = home.error();
    }
    return first;
  }

  driver::Device& device_;
  const AcquisitionPlan& plan_;
  const AcquisitionHooks& hooks_;
  Scan scan_;
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

protocol::Expected<Scan, AcquisitionError> acquire(driver::Device& device, const AcquisitionPlan& plan,
                                                   const AcquisitionHooks& hooks) {
  return Run(device, plan, hooks).execute();
}

}  // namespace ldoem::scan
