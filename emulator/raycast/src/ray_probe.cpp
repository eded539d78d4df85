#include "ray_probe.hpp"

#include <algorithm>
#include <cmath>

namespace ldoem::raycast::detail {

std::optional<CheckedRay> check_ray(const Ray& ray) {
  if (!ray.origin_m.allFinite() || !ray.direction.allFinite()) return std::nullopt;
  if (!std::isfinite(ray.max_range_m) || !(ray.max_range_m > 0.0)) return std::nullopt;
  // ODE squares coordinates; beyond this its intermediate values overflow to Inf/NaN and its
  // internal assertions abort the process.
  if (!(ray.origin_m.cwiseAbs().maxCoeff() <= kMaxCoordinate_m)) return std::nullopt;
  const double length = ray.direction.norm();
  // Below this a direction carries no usable angle (and its square underflows).
  if (!(length > 1e-150) || !std::isfinite(length)) return std::nullopt;
  return CheckedRay{ray.origin_m, ray.direction / length, std::min(ray.max_range_m, kMaxCoordinate_m)};
}

RayGeomPool::~RayGeomPool() {
  for (dGeomID geom : free_) dGeomDestroy(geom);
}

RayGeomPool::Lease RayGeomPool::borrow(const CheckedRay& ray) {
  ensure_ode_ready_for_this_thread();
  dGeomID geom = nullptr;
  {
    std::lock_guard lock(mutex_);
    if (!free_.empty()) {
      geom = free_.back();
      free_.pop_back();
    }
  }
  if (geom == nullptr) {
    geom = dCreateRay(nullptr, ray.max_range_m);
    // For trimeshes: report the nearest triangle, from either side.
    dGeomRaySetFirstContact(geom, 0);
    dGeomRaySetBackfaceCull(geom, 0);
    dGeomRaySetClosestHit(geom, 1);
  }
  dGeomRaySetLength(geom, ray.max_range_m);
  dGeomRaySet(geom, ray.origin_m.x(), ray.origin_m.y(), ray.origin_m.z(), ray.direction.x(),
              ray.direction.y(), ray.direction.z());
  return Lease(*this, geom);
}

void RayGeomPool::give_back(dGeomID geom) {
  std::lock_guard lock(mutex_);
  free_.push_back(geom);
}

Eigen::Vector3d facing_normal(const Eigen::Vector3d& normal, const Eigen::Vector3d& direction) {
  const double length = normal.norm();
  if (!std::isfinite(length) || !(length > 1e-12)) return -direction;
  const Eigen::Vector3d unit = normal / length;
  return unit.dot(direction) > 0.0 ? Eigen::Vector3d(-unit) : unit;
}

namespace {

// How far ahead (in bounding radii) a geom must be before the probe starts near it instead.
constexpr double kNearStartRadii = 1000.0;

// ODE's quadratics lose the object's size when the ray starts far away compared with it (a
// 1e-4 m sphere seen from 1 km: R^2 drops below the rounding of the squared distance) and can
// then hit an assertion that aborts. Starting the probe two bounding radii before the object
// keeps the arithmetic at the object's scale; the skipped distance is added back in double.
// Returns the skipped distance, or nothing if the object is beyond the ray's reach.
std::optional<double> near_start_skip(const CheckedRay& ray, const OdeWorld& world, std::size_t object_index) {
  const double radius_m = world.bounding_radius_m(object_index);
  if (!std::isfinite(radius_m)) return 0.0;  // planes: a single division, nothing to lose
  const double along_m = (world.bounding_centre_m(object_index) - ray.origin_m).dot(ray.direction);
  const double skip_m = along_m - 2.0 * radius_m;
  if (!(skip_m > kNearStartRadii * radius_m)) return 0.0;
  if (skip_m >= ray.max_range_m) return std::nullopt;
  return skip_m;
}

}  // namespace

std::optional<Hit> collide(dGeomID probe, const CheckedRay& ray, const OdeWorld& world,
                           std::size_t object_index) {
  const auto skip_m = near_start_skip(ray, world, object_index);
  if (!skip_m) return std::nullopt;
  if (*skip_m > 0.0) {
    const Eigen::Vector3d start = ray.origin_m + *skip_m * ray.direction;
    dGeomRaySetLength(probe, ray.max_range_m - *skip_m);
    dGeomRaySet(probe, start.x(), start.y(), start.z(), ray.direction.x(), ray.direction.y(), ray.direction.z());
  }
  dContactGeom contact{};
  const int count = dCollide(probe, world.geom(object_index), 1, &contact, sizeof(dContactGeom));
  if (*skip_m > 0.0) {  // the probe serves the other geoms of this cast from the true origin
    dGeomRaySetLength(probe, ray.max_range_m);
    dGeomRaySet(probe, ray.origin_m.x(), ray.origin_m.y(), ray.origin_m.z(), ray.direction.x(),
                ray.direction.y(), ray.direction.z());
  }
  if (count < 1) return std::nullopt;
  const double range_m = contact.depth + *skip_m;
  if (!std::isfinite(range_m) || !(range_m > 0.0) || range_m > ray.max_range_m) return std::nullopt;
  const Eigen::Vector3d normal(contact.normal[0], contact.normal[1], contact.normal[2]);
  return Hit{range_m, facing_normal(normal, ray.direction), world.object(object_index).reflectance,
             static_cast<std::uint32_t>(object_index)};
}

}  // namespace ldoem::raycast::detail
