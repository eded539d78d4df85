#include "ldoem/raycast/ode_ray_caster.hpp"

#include "ray_probe.hpp"

namespace ldoem::raycast {

OdeRayCaster::OdeRayCaster(const OdeWorld& world) : world_(world) {}

OdeRayCaster::~OdeRayCaster() = default;

std::optional<Hit> OdeRayCaster::cast(const Ray& ray) const {
  const auto checked = detail::check_ray(ray);
  if (!checked) return std::nullopt;
  const dGeomID probe = detail::aim_thread_probe(*checked);
  std::optional<detail::Contact> nearest;
  for (std::size_t i = 0; i < world_.object_count(); ++i) {
    if (i == checked->ignored_object) continue;
    const auto contact = detail::collide(probe, *checked, world_, i);
    if (contact && (!nearest || detail::nearer(*contact, *nearest))) nearest = contact;
  }
  if (!nearest) return std::nullopt;
  return detail::to_hit(*nearest, *checked, world_);
}

}  // namespace ldoem::raycast
