// What both casters share: checking a Ray, ODE ray geoms borrowed per call, and turning one
// dCollide contact into a Hit with the guards of docs/scenes.md "Numerical edge cases".
// Internal to ldoem_raycast.
#pragma once

#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/raycast/ray_caster.hpp"

#include <mutex>
#include <optional>
#include <vector>

namespace ldoem::raycast::detail {

// A ray that passed the checks: finite origin, unit direction, finite positive length.
struct CheckedRay {
  Eigen::Vector3d origin_m;
  Eigen::Vector3d direction;
  double max_range_m;
};

// Origins farther out than this (any coordinate) give no hit; longer rays are shortened to it.
// The scene loader rejects numbers beyond the same limit (docs/scenes.md).
inline constexpr double kMaxCoordinate_m = 1e9;

// Nothing for zero-length or non-finite directions, non-finite origins, and ranges that are
// not finite and positive. A non-unit direction is normalised (ranges are in metres).
std::optional<CheckedRay> check_ray(const Ray& ray);

// ODE ray geoms are mutable (dGeomRaySet), so concurrent casts each borrow their own.
class RayGeomPool {
 public:
  RayGeomPool() = default;
  ~RayGeomPool();
  RayGeomPool(const RayGeomPool&) = delete;
  RayGeomPool& operator=(const RayGeomPool&) = delete;

  class Lease {
   public:
    Lease(RayGeomPool& pool, dGeomID geom) : pool_(pool), geom_(geom) {}
    ~Lease() { pool_.give_back(geom_); }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    dGeomID geom() const { return geom_; }

   private:
    RayGeomPool& pool_;
    dGeomID geom_;
  };

  // A ray geom set to `ray`, with closest-hit on and no back-face culling (for trimeshes).
  Lease borrow(const CheckedRay& ray);

 private:
  void give_back(dGeomID geom);

  std::mutex mutex_;
  std::vector<dGeomID> free_;
};

// dCollide(probe, geom) as a Hit: range in (0, max_range], finite unit normal turned to face
// the ray. Nothing otherwise.
std::optional<Hit> collide(dGeomID probe, const CheckedRay& ray, const OdeWorld& world,
                           std::size_t object_index);

// Hit::normal is the surface normal turned against the ray; a degenerate one becomes -direction.
Eigen::Vector3d facing_normal(const Eigen::Vector3d& normal, const Eigen::Vector3d& direction);

}  // namespace ldoem::raycast::detail
