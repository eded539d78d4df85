#include "ldoem/daemon/scene_adapters.hpp"

#include <algorithm>
#include <numbers>

#include "ldoem/motor/head_drive.hpp"

namespace ldoem::daemon {
namespace {

// Used when the curve never reaches the target (friction too high for the drive): the control
// unit still needs an answer, and S1/S2 give up after 5 s / 10 s anyway (spec 6).
constexpr SimTime kUnreachableSpinUp = std::chrono::seconds(10);

double hz_to_rad_s(double hz) { return 2.0 * std::numbers::pi * hz; }

}  // namespace

double head_ticks_to_rad(std::uint32_t angle_ticks) {
  return static_cast<double>(angle_ticks) * (2.0 * std::numbers::pi / kHeadTicksPerRevolution);
}

SimTime SpinUpHeadModel::time_to_reach(double from_hz, double to_hz) const {
  const motor::SpinUpCurve curve(config_, SimTime::zero(), hz_to_rad_s(from_hz), 0.0, hz_to_rad_s(to_hz));
  const std::optional<SimTime> reached = to_hz == 0.0
                                             ? curve.holds_target_from()
                                             : curve.first_within(hz_to_rad_s(to_hz), motor::kSpeedReachedTolerance);
  return reached.value_or(kUnreachableSpinUp);
}

SceneMeasurement::SceneMeasurement(const sensor::SensorModel& sensor, TiltTrack& tilt, bool sweep_motion,
                                   RevolutionStart revolution_start, const HeadTrack* head)
    : sensor_(sensor),
      tilt_(tilt),
      sweep_motion_(sweep_motion),
      revolution_start_(std::move(revolution_start)),
      head_(head) {}

void SceneMeasurement::measure(std::uint64_t revolution, std::span<const control::BeamQuery> beams,
                               std::span<control::BeamReturn> returns) {
  ++revolutions_measured_;
  if (beams.empty()) {
    return;
  }
  SimTime last_beam = beams.front().time;
  for (const auto& beam : beams) {
    last_beam = std::max(last_beam, beam.time);
  }
  tilt_.advance_to(last_beam);
  const double frozen_tilt = tilt_.tilt_at(revolution_start_(revolution, beams.front().time));

  requests_.resize(beams.size());
  samples_.resize(beams.size());
  for (std::size_t i = 0; i < beams.size(); ++i) {
    requests_[i] = sensor::BeamRequest{head_ticks_to_rad(beams[i].angle_ticks),
                                       sweep_motion_ ? tilt_.tilt_at(beams[i].time) : frozen_tilt,
                                       beams[i].beam_index};
  }
  if (head_ != nullptr) {  // D9 head_dynamics: the ray goes where the mirror really points
    for (std::size_t i = 0; i < beams.size(); ++i) {
      requests_[i].head_angle_rad += head_->deviation_rad(beams[i].time);
    }
  }
  // D6 keys the noise by revolution; the sensor takes 32 bits (wraps after 13 years at 10 Hz).
  sensor_.measure(static_cast<std::uint32_t>(revolution), requests_, samples_);
  for (std::size_t i = 0; i < beams.size() && i < returns.size(); ++i) {
    returns[i] = control::BeamReturn{samples_[i].distance, samples_[i].echo};
  }
}

}  // namespace ldoem::daemon
