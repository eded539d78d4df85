#include "ldoem/raycast/ode_ray_caster.hpp"

#include "ray_probe.hpp"

namespace ldoem::raycast {

OdeRayCaster::OdeRayCaster(const OdeWorld& world)
    : world_(world), probes_(std::make_unique<detail::RayGeomPool>()) {}

OdeRayCaster::~OdeRayCaster() = default;

std::optional<Hit> OdeRayCaster::cast(const Ray& ray) const {
  const auto checked = detail::check_ray(ray);
  if (!checked) return std::nullopt;
  const auto probe = probes_->borrow(*checked);
  std::optional<Hit> nearest;
  for (std::size_t i = 0; i < world_.object_count(); ++i) {
    const auto hit = detail::collide(probe.geom(), *checked, world_, i);
    if (hit && (!nearest || hit->range_m < nearest->range_m)) nearest = hit;
  }
  return nearest;
}

}  // namespace ldoem::raycast
