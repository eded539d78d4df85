// One 3D scan as the paper's acquisition runs it, at the sensor + motor level (the daemon and the
// wire are not involved): the head spins at 10 Hz, the tilt motor is stepped to the low apex,
// then for every layer one revolution's profile is measured and the plate is moved by the layer
// step (2 full-step pulses at step_rate_hz) after the profile's last beam. Virtual time only
// (D7): the result says how many simulated seconds the scan spans, so callers can report
// simulated seconds per wall second.
//
// The scene's effects decide the rest, as the emulator would: motor_dynamics picks the ODE hinge
// (emulator/physics/motor), head_dynamics shifts each beam's time by the speed ripple (the daemon's
// motor::HeadRippleTrack; angles stay nominal), sweep_motion takes each beam's tilt at its own time (otherwise the tilt is frozen at the
// profile's first beam), and the sensor model runs the scene's pipeline.
#pragma once

#include "bench_scenes.hpp"

#include <ldoem/scene/scene.hpp>
#include <ldoem/sensor/sensor_model.hpp>

#include <cstdint>
#include <vector>

namespace ldoem::bench {

struct PaperScanOptions {
  AngleGrid head = kPaperHead;
  AngleGrid tilt = kPaperTilt;
  double revolution_hz = 10.0;
  double step_rate_hz = 500.0;  // full steps per second: below the motor's rated 636 (docs/sensor-model.md)
};

struct PaperScanResult {
  std::vector<sensor::BeamRequest> beams;  // every beam of the scan, layer by layer
  std::vector<sensor::BeamSample> samples;
  std::vector<double> ideal_tilt_rad;      // the grid tilt of each beam's layer
  double simulated_s = 0.0;                // from the first pulse to the end of the last revolution
  std::uint64_t rays_cast = 0;
  std::uint64_t random_draws = 0;
};

[[nodiscard]] PaperScanResult run_paper_scan(const scene::Scene& scene, const sensor::SensorModel& sensor,
                                             const PaperScanOptions& options = {});

// RMS and largest |tilt - ideal tilt| over all beams, radians.
struct TiltError {
  double rms_rad = 0.0;
  double max_rad = 0.0;
};
[[nodiscard]] TiltError tilt_error(const PaperScanResult& scan);

// World points (D5) of every beam with an echo.
[[nodiscard]] std::vector<Eigen::Vector3d> scan_points(const scene::ScannerConfig& scanner, const PaperScanResult& scan);

}  // namespace ldoem::bench
