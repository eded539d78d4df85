#include "ldoem/plant/scene_ports.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "ldoem/motor/head_drive.hpp"

namespace ldoem::plant {
namespace {

// Used when the curve never reaches the target (friction too high for the drive): the control
// unit still needs an answer, and S1/S2 give up after 5 s / 10 s anyway (spec 6).
constexpr SimTime kUnreachableSpinUp = std::chrono::seconds(10);

double hz_to_rad_s(double hz) { return 2.0 * std::numbers::pi * hz; }

double seconds(SimTime time) { return std::chrono::duration<double>(time).count(); }

// A window of one instant (per_revolution) is widened to this so that it has a length.
constexpr double kMinWorldWindow_s = 1e-6;

}  // namespace

double head_ticks_to_rad(std::uint32_t angle_ticks) {
  return static_cast<double>(angle_ticks) * (2.0 * std::numbers::pi / base::kTicksPerTurn);
}

SimTime SpinUpHeadModel::time_to_reach(double from_hz, double to_hz) const {
  const motor::SpinUpCurve curve(config_, SimTime::zero(), hz_to_rad_s(from_hz), 0.0, hz_to_rad_s(to_hz));
  const std::optional<SimTime> reached = to_hz == 0.0
                                             ? curve.holds_target_from()
                                             : curve.first_within(hz_to_rad_s(to_hz), motor::kSpeedReachedTolerance);
  return reached.value_or(kUnreachableSpinUp);
}

SceneMeasurement::SceneMeasurement(const sensor::SensorModel& sensor, TiltPlate& tilt, bool sweep_motion,
                                   const motor::HeadRippleTrack* head, std::optional<WorldTiming> world)
    : sensor_(sensor), tilt_(tilt), sweep_motion_(sweep_motion), head_(head), world_(std::move(world)) {}

void SceneMeasurement::measure(const control::RevolutionQuery& revolution, std::span<const control::BeamQuery> beams,
                               std::span<control::BeamReturn> returns) {
  if (beams.empty()) {
    return;
  }
  // D9 head_dynamics: each point lies at its nominal angle and fires when the rippling head
  // reaches it; without the effect at its nominal time.
  fire_times_.resize(beams.size());
  for (std::size_t i = 0; i < beams.size(); ++i) {
    fire_times_[i] = head_ != nullptr ? head_->fire_time(revolution.start, beams[i].time) : beams[i].time;
  }
  SimTime last_beam = beams.front().time;
  for (const auto& beam : beams) {
    last_beam = std::max(last_beam, beam.time);
  }
  tilt_.advance_to(last_beam);
  const double frozen_tilt = tilt_.tilt_at(revolution.start);

  requests_.resize(beams.size());
  samples_.resize(beams.size());
  for (std::size_t i = 0; i < beams.size(); ++i) {
    requests_[i] = sensor::BeamRequest{head_ticks_to_rad(beams[i].angle_ticks),
                                       sweep_motion_ ? tilt_.tilt_at(fire_times_[i]) : frozen_tilt,
                                       beams[i].beam_index, 0.0};
  }
  if (world_) {  // D12: each beam sees the world at its own instant (or all at the revolution's start)
    const bool per_beam = world_->beam_time == scene::BeamTime::per_beam;
    double first_s = INFINITY;
    double last_s = -INFINITY;
    for (std::size_t i = 0; i < beams.size(); ++i) {
      const double t_s = seconds(per_beam ? fire_times_[i] : revolution.start);
      requests_[i].time_s = t_s;
      first_s = std::min(first_s, t_s);
      last_s = std::max(last_s, t_s);
    }
    world_->prepare(first_s, std::max(last_s, first_s + kMinWorldWindow_s));
  }
  // D6 keys the noise by revolution; the sensor takes 32 bits (wraps after 13 years at 10 Hz).
  sensor_.measure(static_cast<std::uint32_t>(revolution.number), requests_, samples_);
  for (std::size_t i = 0; i < beams.size() && i < returns.size(); ++i) {
    returns[i] = control::BeamReturn{samples_[i].distance, samples_[i].echo};
  }
}

}  // namespace ldoem::plant
