// Helpers shared by the ray caster tests: scenes built in code, and both casters over them.
#pragma once

#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/raycast/ode_ray_caster.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace ldoem::raycast::testing {

inline scene::SceneObject make_object(scene::Shape shape, Eigen::Vector3d position_m,
                                      Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity(),
                                      double reflectance = 0.8) {
  scene::SceneObject object;
  object.shape = std::move(shape);
  object.pose.position_m = position_m;
  object.pose.orientation = orientation;
  object.reflectance = reflectance;
  return object;
}

inline Ray make_ray(Eigen::Vector3d origin_m, Eigen::Vector3d direction, double max_range_m = 1e6) {
  return Ray{origin_m, direction.normalized(), max_range_m, 0.0};
}

// A scene, its ODE world and one caster of type Caster over it.
template <class Caster>
struct Rig {
  explicit Rig(scene::Scene s) : scene(std::move(s)), world(scene), caster(world) {}
  scene::Scene scene;
  OdeWorld world;
  Caster caster;
};

template <class Caster>
std::unique_ptr<Rig<Caster>> rig_of(std::vector<scene::SceneObject> objects) {
  scene::Scene s;
  s.objects = std::move(objects);
  return std::make_unique<Rig<Caster>>(std::move(s));
}

inline void expect_sane(const std::optional<Hit>& hit, const Ray& ray) {
  if (!hit) return;
  EXPECT_TRUE(std::isfinite(hit->range_m));
  EXPECT_GT(hit->range_m, 0.0);
  EXPECT_LE(hit->range_m, ray.max_range_m);
  EXPECT_TRUE(hit->normal.allFinite());
  EXPECT_NEAR(hit->normal.norm(), 1.0, 1e-9);
  EXPECT_LE(hit->normal.dot(ray.direction), 1e-12);  // faces the ray
}

using CasterTypes = ::testing::Types<OdeRayCaster, EmbreeRayCaster>;

}  // namespace ldoem::raycast::testing
