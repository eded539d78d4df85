// The moving index only narrows the search: a prepared SceneCaster (candidates from boxes swept
// over the window, cylinders about a spin axis, spheres) answers every ray exactly as an
// unprepared one, which tests every moving object. Rays are aimed at points near the objects'
// reach, where a box too tight would lose them.
#include "world_test_support.hpp"

#include <random>

namespace ldoem::world {
namespace {

using testing::kIndexOptions;
using testing::ray_at;

scene::Scene spinning_field() {
  std::mt19937_64 generator(2024);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  scene::Scene scene;
  for (int i = 0; i < 24; ++i) {
    scene::SceneObject object;
    object.name = "o" + std::to_string(i);
    const double size_m = 0.4 + 0.3 * (unit(generator) + 1.0);
    switch (i % 4) {
      case 0: object.shape = scene::Box{Eigen::Vector3d(size_m, 0.3 * size_m, 2.0 * size_m)}; break;
      case 1: object.shape = scene::Cylinder{0.2 * size_m, 3.0 * size_m}; break;
      case 2: object.shape = scene::Capsule{0.15 * size_m, 2.5 * size_m}; break;
      default: object.shape = scene::Sphere{0.5 * size_m}; break;
    }
    object.pose.position_m = Eigen::Vector3d(6 * unit(generator), 6 * unit(generator), 2 * unit(generator));
    object.pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(
        3.0 * unit(generator), Eigen::Vector3d(unit(generator), unit(generator), unit(generator)).normalized()));
    scene::ConstantVelocity velocity;
    velocity.linear_velocity_mps = Eigen::Vector3d(unit(generator), unit(generator), 0.2 * unit(generator));
    // Oblique spin axes (the cylinder bound) and, for every fourth, none (the turned box).
    if (i % 4 != 3) velocity.angular_velocity_rad_s = 4.0 * Eigen::Vector3d(unit(generator), unit(generator), unit(generator));
    object.motion = velocity;
    scene.objects.push_back(std::move(object));
  }
  return scene;
}

TEST(IndexCompleteness, PreparedCasterAnswersAsTheExhaustiveOne) {
  const scene::Scene scene = spinning_field();
  const SceneCaster exhaustive(scene);  // never prepared: every moving object is tested
  std::mt19937_64 generator(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const auto& options : kIndexOptions) {
    SceneCaster indexed(scene, options);
    int hits = 0;
    for (int window = 0; window < 4; ++window) {
      const double t0 = 0.37 * window;
      indexed.prepare(t0, t0 + 0.1);
      for (int k = 0; k < 2000; ++k) {
        const double t = t0 + 0.1 * (unit(generator) + 1.0) / 2.0;
        const std::size_t target = static_cast<std::size_t>((unit(generator) + 1.0) * 12.0) % scene.objects.size();
        // A point around the target within its reach sphere, and a little beyond it.
        const Eigen::Vector3d centre = indexed.motion().pose_at(target, t).position_m;
        const Eigen::Vector3d aim = centre + 1.6 * Eigen::Vector3d(unit(generator), unit(generator), unit(generator));
        const Eigen::Vector3d origin(0.0, 0.0, 8.0 * unit(generator));
        const auto ray = ray_at(origin, aim - origin, t);
        const auto a = indexed.cast(ray);
        const auto b = exhaustive.cast(ray);
        ASSERT_EQ(a.has_value(), b.has_value()) << "window " << window << " ray " << k;
        if (!a) continue;
        ++hits;
        EXPECT_EQ(a->range_m, b->range_m);
        EXPECT_EQ(a->object_index, b->object_index);
      }
    }
    EXPECT_GT(hits, 1000) << "the rays meet the objects";
  }
}

}  // namespace
}  // namespace ldoem::world
