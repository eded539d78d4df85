// The facade the control unit calls: beam requests (head angle, tilt, index) in, encoded samples
// out. It makes the D5 rays, hands them to a RayCaster, and runs the D9 pipeline built from the
// scene's effects.
//
// Tilt per beam is the caller's business: plant::SceneMeasurement (not the control unit) gives
// each beam the tilt at its own time with `sweep_motion`, else the tilt at the start of its
// revolution, the same for every beam of that revolution (D9).
#pragma once

#include <ldoem/raycast/ray_caster.hpp>
#include <ldoem/scene/scene.hpp>
#include <ldoem/sensor/beam_sample.hpp>
#include <ldoem/sensor/effects.hpp>

#include <cstdint>
#include <span>

namespace ldoem::sensor {

struct BeamRequest {
  double head_angle_rad = 0.0;  // D5: 0 = +x, counter-clockwise seen from above
  double tilt_rad = 0.0;        // D5: positive raises the beam plane
  std::uint32_t beam_index = 0; // keys the noise stream together with the revolution (D6)
  double time_s = 0.0;          // D12: when the beam fires (device s); read only if the world moves
};

struct MeasureStats {
  std::uint64_t rays_cast = 0;
  std::uint64_t random_draws = 0;
};

class SensorModel {
 public:
  // Copies what it needs from the scene; keeps a reference to the caster, which must outlive it.
  // Every ray passes through `ignored_object` (issue 15: the scanner's own housing).
  SensorModel(const scene::Scene& scene, const raycast::RayCaster& caster,
              std::uint32_t ignored_object = raycast::kNoObject);

  // Fills out[i] for beams[i]. Measures min(beams.size(), out.size()) beams; out entries beyond
  // beams.size() are set to "no echo". Same inputs -> identical samples, on any thread: const
  // and stateless per call (the caster must be thread-safe const too, as the interface asks).
  void measure(std::uint32_t revolution, std::span<const BeamRequest> beams, std::span<BeamSample> out) const;

  // The same, also returning what it cost (rays cast, random words drawn).
  MeasureStats measure_counted(std::uint32_t revolution, std::span<const BeamRequest> beams,
                               std::span<BeamSample> out) const;

  [[nodiscard]] const EffectPipeline& pipeline() const { return pipeline_; }

 private:
  scene::ScannerConfig scanner_;
  std::uint64_t seed_;
  const raycast::RayCaster& caster_;
  EffectPipeline pipeline_;
  std::uint32_t ignored_object_;
};

}  // namespace ldoem::sensor
