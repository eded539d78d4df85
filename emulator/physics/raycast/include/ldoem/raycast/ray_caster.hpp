// The one question the sensor model asks the geometry: where does this ray first hit?
// Implementations: the Embree BVH over ODE geoms and Embree triangles (the fast one), and plain
// ODE (the reference the tests compare against).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <optional>

namespace ldoem::raycast {

// No object: Ray::ignored_object's default.
inline constexpr std::uint32_t kNoObject = 0xFFFFFFFFu;

struct Ray {
  Eigen::Vector3d origin_m;
  Eigen::Vector3d direction;  // unit length; callers guarantee it, casters guard against others
  double max_range_m;
  // D12: the instant the beam fires, in device seconds. Only casters of a world that moves
  // read it; a static scene's casters ignore it.
  double time_s = 0.0;
  // Issue 15: an object this ray passes through as if it were not there (Scene::objects index):
  // a scanner's own housing, which its beams leave from inside. Honoured for primitives (box,
  // sphere, cylinder, capsule) and moving objects, the shapes a housing takes.
  std::uint32_t ignored_object = kNoObject;
};

struct Hit {
  double range_m;              // along the ray, > 0
  Eigen::Vector3d normal;      // unit, facing against the ray
  double reflectance;          // of the object hit (D6)
  std::uint32_t object_index;  // index into Scene::objects
};

class RayCaster {
 public:
  virtual ~RayCaster() = default;
  // Nearest hit in (0, max_range_m], or nothing. Never NaN: invalid rays give nothing.
  virtual std::optional<Hit> cast(const Ray& ray) const = 0;
};

}  // namespace ldoem::raycast
