// The reference caster: one ODE ray against every geom with dCollide, nearest contact wins.
// O(objects) per ray, exact for primitives (ODE's closed-form tests, double precision).
// Meshes use ODE's trimesh, which may disagree with EmbreeRayCaster at triangle edges
// (docs/scenes.md "Numerical edge cases").
#pragma once

#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/raycast/ray_caster.hpp"

namespace ldoem::raycast {

class OdeRayCaster final : public RayCaster {
 public:
  explicit OdeRayCaster(const OdeWorld& world);  // world must outlive the caster
  ~OdeRayCaster() override;

  // Thread-safe: each thread casts with its own ODE ray geom.
  std::optional<Hit> cast(const Ray& ray) const override;

 private:
  const OdeWorld& world_;
};

}  // namespace ldoem::raycast
