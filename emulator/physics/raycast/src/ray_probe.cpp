#include "ray_probe.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace ldoem::raycast::detail {

namespace {

// Points the ray geom from `start` along `direction` (unit: check_ray made it so). ODE takes a
// ray's direction from the z column of its rotation (what dGeomRaySet writes; the ray tests
// read nothing else of it). Setting that column directly skips dGeomRaySet's renormalisation
// of an already unit vector, which cost ~5 % of a cast on small scenes; both casters aim the
// same way, so they still see identical rays. `rotation` is scratch whose other entries are 0.
void place_probe(dGeomID probe, const Eigen::Vector3d& start, const Eigen::Vector3d& direction,
                 dMatrix3& rotation) {
  rotation[2] = direction.x();
  rotation[6] = direction.y();
  rotation[10] = direction.z();
  dGeomSetPosition(probe, start.x(), start.y(), start.z());
  dGeomSetRotation(probe, rotation);
}

void place_probe(dGeomID probe, const Eigen::Vector3d& start, const Eigen::Vector3d& direction) {
  dMatrix3 rotation{};
  place_probe(probe, start, direction, rotation);
}

// The per-thread probe of aim_thread_probe. The length is remembered because most casts of a
// scan share it (dGeomRaySetLength is skipped then); collide() restores it after a near start.
class ThreadProbe {
 public:
  ThreadProbe() {
    ensure_ode_ready_for_this_thread();
    geom_ = dCreateRay(nullptr, length_m_);
    // For trimeshes: report the nearest triangle, from either side.
    dGeomRaySetFirstContact(geom_, 0);
    dGeomRaySetBackfaceCull(geom_, 0);
    dGeomRaySetClosestHit(geom_, 1);
  }
  ~ThreadProbe() { dGeomDestroy(geom_); }
  ThreadProbe(const ThreadProbe&) = delete;
  ThreadProbe& operator=(const ThreadProbe&) = delete;

  dGeomID aim(const CheckedRay& ray) {
    if (ray.max_range_m != length_m_) {
      dGeomRaySetLength(geom_, ray.max_range_m);
      length_m_ = ray.max_range_m;
    }
    place_probe(geom_, ray.origin_m, ray.direction, rotation_);
    return geom_;
  }

 private:
  double length_m_ = 1.0;
  dGeomID geom_ = nullptr;
  dMatrix3 rotation_{};  // zeroed once here rather than on every cast
};

}  // namespace

dGeomID aim_thread_probe(const CheckedRay& ray) {
  thread_local ThreadProbe probe;
  return probe.aim(ray);
}

Eigen::Vector3d facing_normal(const Eigen::Vector3d& normal, const Eigen::Vector3d& direction) {
  const double squared_length = normal.squaredNorm();
  // Unit to within rounding (planes, boxes, mesh triangles, whose normals are unit already):
  // normalising again would move it by an ulp at the price of a square root and a division.
  if (std::abs(squared_length - 1.0) <= kUnitSquaredLengthTolerance) {
    return normal.dot(direction) > 0.0 ? Eigen::Vector3d(-normal) : normal;
  }
  const double length = std::sqrt(squared_length);
  if (!std::isfinite(length) || !(length > 1e-12)) return -direction;
  const Eigen::Vector3d unit = normal * (1.0 / length);  // one division, not three
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

std::optional<Contact> collide(dGeomID probe, const CheckedRay& ray, const OdeWorld& world,
                               std::size_t object_index, bool every_contact) {
  const auto skip_m = near_start_skip(ray, world, object_index);
  if (!skip_m) return std::nullopt;
  if (*skip_m > 0.0) {
    const Eigen::Vector3d start = ray.origin_m + *skip_m * ray.direction;
    dGeomRaySetLength(probe, ray.max_range_m - *skip_m);
    place_probe(probe, start, ray.direction);
  }
  // Filled by ODE up to the count it returns; read only that far.
  std::array<dContactGeom, kMeshContacts> contacts;
  if (every_contact) dGeomRaySetClosestHit(probe, 0);
  const int count = dCollide(probe, world.geom(object_index), every_contact ? kMeshContacts : 1, contacts.data(), sizeof(dContactGeom));
  if (every_contact) dGeomRaySetClosestHit(probe, 1);
  if (*skip_m > 0.0) {  // the probe serves the other geoms of this cast from the true origin
    dGeomRaySetLength(probe, ray.max_range_m);
    place_probe(probe, ray.origin_m, ray.direction);
  }
  std::optional<Contact> best;
  for (int i = 0; i < count; ++i) {
    const dContactGeom& contact = contacts[static_cast<std::size_t>(i)];
    const double range_m = contact.depth + *skip_m;
    if (!std::isfinite(range_m) || !(range_m > 0.0) || range_m > ray.max_range_m) continue;
    if (best && !(range_m < best->range_m)) continue;
    best = Contact{range_m, Eigen::Vector3d(contact.normal[0], contact.normal[1], contact.normal[2]), object_index};
  }
  return best;
}

Hit to_hit(const Contact& contact, const CheckedRay& ray, const OdeWorld& world) {
  return Hit{contact.range_m, facing_normal(contact.normal, ray.direction),
             scene::optical_reflectance(world.object(contact.object_index)), static_cast<std::uint32_t>(contact.object_index)};
}

}  // namespace ldoem::raycast::detail
