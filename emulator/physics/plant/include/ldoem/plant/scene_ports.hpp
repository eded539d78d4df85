// The control unit's two questions to the physics (ports.hpp), answered by the scene's models:
// - HeadModel: how long a head speed change takes, from the D7 spin-up curve of motor/head_drive.
// - MeasurementSource: the ranges of one revolution, from the sensor model with the head angle
//   of each point (1/16 deg ticks, D5) and the plate's tilt from the tilt plate: at each point's
//   own time with sweep_motion, otherwise frozen at the revolution's start (D9). With
//   head_dynamics each point still lies at its nominal angle (the LD fires on encoder ticks) but
//   fires at the time the rippling head reaches it (motor/head_ripple_track.hpp, the model the
//   benchmarks use too); that time is the point's own time (tilt under sweep_motion, the beam's
//   instant for a moving world).
#pragma once

#include <functional>
#include <optional>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/control/ports.hpp"
#include "ldoem/motor/head_ripple_track.hpp"
#include "ldoem/plant/tilt_plate.hpp"
#include "ldoem/scene/scene.hpp"
#include "ldoem/sensor/sensor_model.hpp"

namespace ldoem::plant {

using base::SimTime;

// Head angle in encoder ticks (base::kTicksPerTurn per turn, spec 6) to radians.
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
  // `head` is null without head_dynamics (D9): then every point fires at its nominal time and
  // nothing is computed per point for the head. `world` is empty unless the scene moves (D12).
  SceneMeasurement(const sensor::SensorModel& sensor, TiltPlate& tilt, bool sweep_motion,
                   const motor::HeadRippleTrack* head = nullptr, std::optional<WorldTiming> world = std::nullopt);

  // Without sweep_motion the tilt is frozen at `revolution.start` (D9).
  void measure(const control::RevolutionQuery& revolution, std::span<const control::BeamQuery> beams,
               std::span<control::BeamReturn> returns) override;

 private:
  const sensor::SensorModel& sensor_;
  TiltPlate& tilt_;
  bool sweep_motion_;
  const motor::HeadRippleTrack* head_;
  std::optional<WorldTiming> world_;
  std::vector<SimTime> fire_times_;            // reused per revolution
  std::vector<sensor::BeamRequest> requests_;  // reused per revolution
  std::vector<sensor::BeamSample> samples_;
};

}  // namespace ldoem::plant
