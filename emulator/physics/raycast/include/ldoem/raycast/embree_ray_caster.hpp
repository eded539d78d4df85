// The fast caster: an Embree 3 BVH finds candidates, exact double-precision tests answer them.
// - Primitives (box, sphere, cylinder, capsule) are one Embree user geometry whose bounds are
//   the ODE geoms' AABBs (padded, rounded outwards to float); its intersect callback runs a
//   closed-form ray test in double precision on the geom's own parameters (read from ODE), so
//   answers equal OdeRayCaster's dCollide (same object, range within 1e-9 m: tests/raycast)
//   without the cost of aiming an ODE ray and dispatching dCollide per candidate.
// - Planes are unbounded: they are tested directly (one division each), before the BVH query.
// - Meshes are Embree triangle geometry in a RTC_SCENE_FLAG_ROBUST scene (watertight at
//   edges); the range of the triangle hit is then recomputed in double precision.
// Embree works in float, so its coordinates are relative to the centre of the scene's bounds
// (a scene 1e5 m from the origin loses nothing). The BVH is built once, in the constructor.
// A ray whose reach misses the box around everything Embree holds (with a margin larger than
// the float copy's rounding) skips the Embree call: only the planes can answer it.
#pragma once

#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/raycast/ray_caster.hpp"

#include <memory>

namespace ldoem::raycast {

class EmbreeRayCaster final : public RayCaster {
 public:
  explicit EmbreeRayCaster(const OdeWorld& world);  // world must outlive the caster
  ~EmbreeRayCaster() override;
  EmbreeRayCaster(const EmbreeRayCaster&) = delete;
  EmbreeRayCaster& operator=(const EmbreeRayCaster&) = delete;

  // Const and thread-safe: a cast keeps its state on the stack (no lock, no ODE call).
  std::optional<Hit> cast(const Ray& ray) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldoem::raycast
