// The base cast: one ray per beam. Not a D9 effect; replaced by mixed_pixels when that is named.
#include "hit_geometry.hpp"

#include <ldoem/sensor/effects.hpp>

namespace ldoem::sensor {
namespace {

class SingleRayStage final : public BeamStage {
 public:
  std::string_view name() const override { return "single_ray"; }
  std::string describe() const override { return "single_ray: one ray per beam"; }

  void apply(BeamState& beam, const BeamContext& context, BeamCounters& counters) const override {
    ++counters.rays_cast;
    const std::optional<raycast::Hit> hit = context.caster.cast(beam.ray);
    if (!hit || !detail::usable_hit(*hit)) {
      beam.has_return = false;
      return;
    }
    beam.has_return = true;
    beam.range_m = hit->range_m;
    beam.cos_incidence = detail::cos_incidence(beam.ray.direction, hit->normal);
    beam.reflectance = hit->reflectance;
  }
};

}  // namespace

std::unique_ptr<BeamStage> make_single_ray_stage() { return std::make_unique<SingleRayStage>(); }

}  // namespace ldoem::sensor
