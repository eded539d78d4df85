// The control unit's two questions to the physics (ports.hpp), answered by the scene's models:
// - HeadModel: how long a head speed change takes, from the D7 spin-up curve of motor/head_drive.
// - MeasurementSource: the ranges of one revolution, from the sensor model with the head angle
//   of each point (1/16 deg ticks, D5) and the plate's tilt from the tilt track: at each point's
//   own time with sweep_motion, otherwise frozen at the revolution's start (D9). With
//   head_dynamics each ray is cast at the head's true angle (nominal + HeadTrack's deviation at
//   the point's time); the reported angles stay nominal (head_track.hpp).
#pragma once

#include <functional>
#include <optional>

#include "ldoem/control/ports.hpp"
#include "ldoem/daemon/head_track.hpp"
#include "ldoem/daemon/tilt_track.hpp"
#include "ldoem/scene/scene.hpp"
#include "ldoem/sensor/sensor_model.hpp"

namespace ldoem::daemon {

// Spec 6: 5760 encoder ticks per head revolution.
inline constexpr double kHeadTicksPerRevolution = 5760.0;

double head_ticks_to_rad(std::uint32_t angle_ticks);

class SpinUpHeadModel final : public control::HeadModel {
 public:
  explicit SpinUpHeadModel(const scene::HeadConfig& config) : config_(config) {}
  // D7: until the speed is within 1 % of the target (exactly the target when stopping).
  SimTime time_to_reach(double from_hz, double to_hz) const override;

 private:
  scene::HeadConfig config_;
};

// D12, set only when the scene moves: `prepare` readies the world for beams timed in [t0, t1]
// (device seconds); `beam_time` gives each beam its own instant or the revolution's start.
struct WorldTiming {
  std::function<void(double t0_s, double t1_s)> prepare;
  scene::BeamTime beam_time = scene::BeamTime::per_beam;
};

class SceneMeasurement final : public control::MeasurementSource {
 public:
  // The revolution's start time for a PROFILECOUNT revolution number (the daemon derives it
  // from the control unit's head epoch).
  using RevolutionStart = std::function<SimTime(std::uint64_t revolution, SimTime first_beam_time)>;

  // `head` is null without head_dynamics (D9): then every ray is cast at its nominal angle and
  // nothing is computed per point for the head.
  SceneMeasurement(const sensor::SensorModel& sensor, TiltTrack& tilt, bool sweep_motion,
                   RevolutionStart revolution_start, const HeadTrack* head = nullptr,
                   std::optional<WorldTiming> world = std::nullopt);

  void measure(std::uint64_t revolution, std::span<const control::BeamQuery> beams,
               std::span<control::BeamReturn> returns) override;

  std::uint64_t revolutions_measured() const { return revolutions_measured_; }

 private:
  const sensor::SensorModel& sensor_;
  TiltTrack& tilt_;
  bool sweep_motion_;
  RevolutionStart revolution_start_;
  const HeadTrack* head_;
  std::optional<WorldTiming> world_;
  std::vector<sensor::BeamRequest> requests_;  // reused per revolution
  std::vector<sensor::BeamSample> samples_;
  std::uint64_t revolutions_measured_ = 0;
};

}  // namespace ldoem::daemon
