#include "paper_scan.hpp"

#include <ldoem/motor/head_drive.hpp>
#include <ldoem/motor/head_ripple_track.hpp>
#include <ldoem/motor/tilt_motor.hpp>
#include <ldoem/sensor/beam_geometry.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>

namespace ldoem::bench {
namespace {

using base::SimTime;
using scene::Effect;

SimTime from_seconds(double seconds) {
  return std::chrono::duration_cast<SimTime>(std::chrono::duration<double>(seconds));
}

// A revolution starts with the head at -180 deg, so a beam at head angle theta comes
// (theta + 180 deg) / (360 deg * f) after the revolution's start.
constexpr double kRevolutionStartAngleRad = -std::numbers::pi;
// The moves between layers start this long after a profile's last beam.
constexpr double kPulseDelayAfterProfile_s = 0.002;

struct Timeline {
  double revolution_s;
  double head_rad_s;
  SimTime scan_start;
  SimTime first_revolution;
};

void send_pulses(motor::TiltMotor& tilt, SimTime first, int count, int direction, double rate_hz) {
  for (int i = 0; i < count; ++i) tilt.on_step_pulse(first + from_seconds(i / rate_hz), direction, false);
}

}  // namespace

PaperScanResult run_paper_scan(const scene::Scene& scene, const sensor::SensorModel& sensor,
                               const PaperScanOptions& options) {
  const auto tilt_motor = motor::make_tilt_motor(scene);
  const auto head = motor::make_head_drive(scene);
  const bool sweep_motion = scene.effects.has(Effect::sweep_motion);
  const bool head_dynamics = scene.effects.has(Effect::head_dynamics);

  Timeline timeline{};
  timeline.revolution_s = 1.0 / options.revolution_hz;
  timeline.head_rad_s = 2.0 * std::numbers::pi * options.revolution_hz;
  head->set_target(SimTime::zero(), options.revolution_hz);
  // head_dynamics: the daemon's model (motor/head_ripple_track.hpp): points stay at their nominal
  // angles and fire at shifted times.
  std::optional<motor::HeadRippleTrack> ripple;
  if (head_dynamics) {
    ripple.emplace(scene.scanner.head);
    ripple->set_target(SimTime::zero(), options.revolution_hz);
  }
  // D7: the scan starts once TRANS_ROTATE would have answered, plus a margin.
  timeline.scan_start = head->reached_at(options.revolution_hz).value_or(SimTime::zero()) + from_seconds(0.5);

  const double full_step_deg = scene.scanner.tilt_motor.step_angle_deg / scene.scanner.tilt_motor.gear_ratio;
  const int steps_to_low_apex = static_cast<int>(std::lround(-options.tilt.first_deg / full_step_deg));
  const int steps_per_layer = static_cast<int>(std::lround(options.tilt.step_deg / full_step_deg));
  tilt_motor->advance_to(timeline.scan_start);
  send_pulses(*tilt_motor, timeline.scan_start, std::abs(steps_to_low_apex), steps_to_low_apex > 0 ? -1 : 1,
              options.step_rate_hz);
  const double move_s = std::abs(steps_to_low_apex) / options.step_rate_hz + 0.05;
  timeline.first_revolution =
      timeline.scan_start + from_seconds(std::ceil(move_s / timeline.revolution_s) * timeline.revolution_s);

  PaperScanResult result;
  const std::size_t beam_total = static_cast<std::size_t>(options.head.count) * options.tilt.count;
  result.beams.reserve(beam_total);
  result.ideal_tilt_rad.reserve(beam_total);
  result.samples.resize(beam_total);

  std::vector<SimTime> beam_times(static_cast<std::size_t>(options.head.count));
  for (int layer = 0; layer < options.tilt.count; ++layer) {
    const SimTime revolution_start = timeline.first_revolution + from_seconds(layer * timeline.revolution_s);
    const double ideal_tilt_rad = options.tilt.angle_rad(layer);
    const std::size_t layer_first = result.beams.size();
    for (int beam = 0; beam < options.head.count; ++beam) {
      const double nominal_rad = options.head.angle_rad(beam);
      const double since_start_rad = nominal_rad - kRevolutionStartAngleRad;
      beam_times[beam] = revolution_start + from_seconds(since_start_rad / timeline.head_rad_s);
      if (ripple) beam_times[beam] += ripple->fire_time_shift(revolution_start, since_start_rad);
    }
    tilt_motor->advance_to(beam_times.front());
    const double frozen_tilt_rad = tilt_motor->tilt_rad();
    for (int beam = 0; beam < options.head.count; ++beam) {
      sensor::BeamRequest request;
      request.head_angle_rad = options.head.angle_rad(beam);
      if (sweep_motion) {
        tilt_motor->advance_to(beam_times[beam]);
        request.tilt_rad = tilt_motor->tilt_rad();
      } else {
        request.tilt_rad = frozen_tilt_rad;
      }
      request.beam_index = static_cast<std::uint32_t>(beam);
      result.beams.push_back(request);
      result.ideal_tilt_rad.push_back(ideal_tilt_rad);
    }
    const auto stats = sensor.measure_counted(
        static_cast<std::uint32_t>(layer), std::span(result.beams).subspan(layer_first),
        std::span(result.samples).subspan(layer_first, static_cast<std::size_t>(options.head.count)));
    result.rays_cast += stats.rays_cast;
    result.random_draws += stats.random_draws;
    if (layer + 1 < options.tilt.count) {
      send_pulses(*tilt_motor, beam_times.back() + from_seconds(kPulseDelayAfterProfile_s), steps_per_layer, 1,
                  options.step_rate_hz);
    }
  }
  const SimTime scan_end = timeline.first_revolution + from_seconds(options.tilt.count * timeline.revolution_s);
  tilt_motor->advance_to(scan_end);
  result.simulated_s = std::chrono::duration<double>(scan_end - timeline.scan_start).count();
  return result;
}

TiltError tilt_error(const PaperScanResult& scan) {
  TiltError error;
  double sum_squares = 0.0;
  for (std::size_t i = 0; i < scan.beams.size(); ++i) {
    const double e = scan.beams[i].tilt_rad - scan.ideal_tilt_rad[i];
    sum_squares += e * e;
    error.max_rad = std::max(error.max_rad, std::abs(e));
  }
  if (!scan.beams.empty()) error.rms_rad = std::sqrt(sum_squares / static_cast<double>(scan.beams.size()));
  return error;
}

std::vector<Eigen::Vector3d> scan_points(const scene::ScannerConfig& scanner, const PaperScanResult& scan) {
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < scan.beams.size(); ++i) {
    if (scan.samples[i].distance == 0) continue;
    const double range_m = scan.samples[i].distance / sensor::kDistanceUnitsPerMetre;
    points.push_back(sensor::beam_point_world(scanner, scan.beams[i].head_angle_rad, scan.beams[i].tilt_rad, range_m));
  }
  return points;
}

}  // namespace ldoem::bench
