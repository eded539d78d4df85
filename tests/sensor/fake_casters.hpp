// Analytic RayCaster fakes: the sensor tests never need ODE or Embree.
#pragma once

#include <ldoem/raycast/ray_caster.hpp>

#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

namespace ldoem::sensor::testing {

// Infinite plane n . p = offset (n unit), one reflectance.
class PlaneCaster final : public raycast::RayCaster {
 public:
  PlaneCaster(Eigen::Vector3d normal, double offset_m, double reflectance)
      : normal_(normal.normalized()), offset_m_(offset_m), reflectance_(reflectance) {}

  std::optional<raycast::Hit> cast(const raycast::Ray& ray) const override {
    ++casts;
    const double denominator = normal_.dot(ray.direction);
    if (std::abs(denominator) < 1e-12) return std::nullopt;
    const double range_m = (offset_m_ - normal_.dot(ray.origin_m)) / denominator;
    if (!(range_m > 0.0) || range_m > ray.max_range_m) return std::nullopt;
    const Eigen::Vector3d facing = denominator < 0.0 ? normal_ : Eigen::Vector3d(-normal_);
    return raycast::Hit{.range_m = range_m, .normal = facing, .reflectance = reflectance_, .object_index = 0};
  }

  mutable std::atomic<long> casts{0};

 private:
  Eigen::Vector3d normal_;
  double offset_m_;
  double reflectance_;
};

// A wall facing the scanner at x = distance (normal -x towards the origin).
inline PlaneCaster wall_at(double distance_m, double reflectance = 1.0) {
  return PlaneCaster(Eigen::Vector3d::UnitX(), distance_m, reflectance);
}

// Sphere of a radius at a centre, hit from outside.
class SphereCaster final : public raycast::RayCaster {
 public:
  SphereCaster(Eigen::Vector3d centre_m, double radius_m, double reflectance)
      : centre_m_(centre_m), radius_m_(radius_m), reflectance_(reflectance) {}

  std::optional<raycast::Hit> cast(const raycast::Ray& ray) const override {
    const Eigen::Vector3d to_centre = centre_m_ - ray.origin_m;
    const double along = to_centre.dot(ray.direction);
    const double miss_sq = to_centre.squaredNorm() - along * along;
    if (miss_sq > radius_m_ * radius_m_) return std::nullopt;
    const double range_m = along - std::sqrt(radius_m_ * radius_m_ - miss_sq);
    if (!(range_m > 0.0) || range_m > ray.max_range_m) return std::nullopt;
    const Eigen::Vector3d normal = (ray.origin_m + range_m * ray.direction - centre_m_).normalized();
    return raycast::Hit{.range_m = range_m, .normal = normal, .reflectance = reflectance_, .object_index = 0};
  }

 private:
  Eigen::Vector3d centre_m_;
  double radius_m_;
  double reflectance_;
};

// A depth step seen from the origin along +x: walls facing the scanner at x = near for rays
// with direction y >= 0 and at x = far for y < 0. The edge is the plane y = 0.
class DepthStepCaster final : public raycast::RayCaster {
 public:
  DepthStepCaster(double near_x_m, double far_x_m, double reflectance)
      : near_(Eigen::Vector3d::UnitX(), near_x_m, reflectance), far_(Eigen::Vector3d::UnitX(), far_x_m, reflectance) {}
  std::optional<raycast::Hit> cast(const raycast::Ray& ray) const override {
    return ray.direction.y() >= 0.0 ? near_.cast(ray) : far_.cast(ray);
  }

 private:
  PlaneCaster near_;
  PlaneCaster far_;
};

// A caster that breaks its contract: every hit has this range (NaN, inf, 0, negative).
class BrokenRangeCaster final : public raycast::RayCaster {
 public:
  explicit BrokenRangeCaster(double range_m) : range_m_(range_m) {}
  std::optional<raycast::Hit> cast(const raycast::Ray&) const override {
    return raycast::Hit{.range_m = range_m_, .normal = -Eigen::Vector3d::UnitX(), .reflectance = 1.0, .object_index = 0};
  }

 private:
  double range_m_;
};

class MissCaster final : public raycast::RayCaster {
 public:
  std::optional<raycast::Hit> cast(const raycast::Ray&) const override { return std::nullopt; }
};

}  // namespace ldoem::sensor::testing
