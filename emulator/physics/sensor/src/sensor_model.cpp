#include <ldoem/sensor/beam_geometry.hpp>
#include <ldoem/sensor/sensor_model.hpp>

#include <algorithm>

namespace ldoem::sensor {

SensorModel::SensorModel(const scene::Scene& scene, const raycast::RayCaster& caster, std::uint32_t ignored_object)
    : scanner_(scene.scanner),
      seed_(scene.seed),
      caster_(caster),
      pipeline_(EffectPipeline::build(scene.scanner, scene.effects)),
      ignored_object_(ignored_object) {}

void SensorModel::measure(std::uint32_t revolution, std::span<const BeamRequest> beams,
                          std::span<BeamSample> out) const {
  (void)measure_counted(revolution, beams, out);
}

MeasureStats SensorModel::measure_counted(std::uint32_t revolution, std::span<const BeamRequest> beams,
                                          std::span<BeamSample> out) const {
  BeamCounters counters;
  const std::size_t measured = std::min(beams.size(), out.size());
  const double cast_range_m = pipeline_.cast_range_m();
  for (std::size_t i = 0; i < measured; ++i) {
    const BeamRequest& request = beams[i];
    raycast::Ray ray = scanner_.pivot_motion
                           ? beam_ray(world_from_optical(scene::pose_at(*scanner_.pivot_motion, scanner_.pivot_pose,
                                                                        request.time_s),
                                                         scanner_.optical_offset_m, request.tilt_rad),
                                      request.head_angle_rad, cast_range_m)
                           : beam_ray(scanner_, request.head_angle_rad, request.tilt_rad, cast_range_m);
    ray.time_s = request.time_s;
    ray.ignored_object = ignored_object_;
    const BeamContext context{
        .caster = caster_, .seed = seed_, .revolution = revolution, .beam_index = request.beam_index};
    out[i] = pipeline_.run(ray, context, counters);
  }
  std::fill(out.begin() + static_cast<std::ptrdiff_t>(measured), out.end(), BeamSample{});
  return MeasureStats{.rays_cast = counters.rays_cast, .random_draws = counters.random_draws};
}

}  // namespace ldoem::sensor
