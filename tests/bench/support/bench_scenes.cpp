#include "bench_scenes.hpp"

#include "tessellate.hpp"

#include <ldoem/scene/scene_loader.hpp>
#include <ldoem/sensor/beam_geometry.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>

namespace ldoem::bench {
namespace {

// Uniform in [low, high) from 53 random bits: the same numbers on every standard library
// (std::uniform_real_distribution is implementation-defined).
double uniform(std::mt19937_64& generator, double low, double high) {
  const double unit = static_cast<double>(generator() >> 11) * 0x1.0p-53;
  return low + (high - low) * unit;
}

}  // namespace

std::filesystem::path source_dir() {
  if (const char* from_environment = std::getenv("LDOEM_SOURCE_DIR")) return from_environment;
  return LDOEM_SOURCE_DIR;
}

scene::Scene load_repository_scene(const std::string& relative_path) {
  auto loaded = scene::load_scene(source_dir() / relative_path);
  if (!loaded) {
    std::fprintf(stderr, "cannot load %s: %s\n", relative_path.c_str(), loaded.error().message().c_str());
    std::exit(2);
  }
  return std::move(*loaded);
}

scene::Scene random_primitive_scene(std::size_t count, std::uint64_t seed) {
  std::mt19937_64 generator(seed);
  scene::Scene result;
  result.source_path = "generated:random-" + std::to_string(count);
  result.scanner.pivot_pose.position_m = Eigen::Vector3d(0, 0, 0.5);
  result.objects.push_back({"floor", scene::Plane{Eigen::Vector3d::UnitZ(), 0.0}, {}, 0.4, {}, {}});
  for (std::size_t i = 0; i < count; ++i) {
    const double radius_m = uniform(generator, 2.0, 15.0);
    const double azimuth = uniform(generator, -std::numbers::pi, std::numbers::pi);
    scene::SceneObject object;
    object.name = "p" + std::to_string(i);
    object.pose.position_m = Eigen::Vector3d(radius_m * std::cos(azimuth), radius_m * std::sin(azimuth),
                                             uniform(generator, 0.0, 2.0));
    object.pose.orientation = Eigen::AngleAxisd(uniform(generator, 0, std::numbers::pi), Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(uniform(generator, 0, std::numbers::pi), Eigen::Vector3d::UnitX());
    const double size_m = uniform(generator, 0.1, 0.6);
    switch (i % 4) {
      case 0: object.shape = scene::Box{Eigen::Vector3d(size_m, 0.7 * size_m, 1.3 * size_m)}; break;
      case 1: object.shape = scene::Sphere{0.5 * size_m}; break;
      case 2: object.shape = scene::Cylinder{0.3 * size_m, 1.5 * size_m}; break;
      default: object.shape = scene::Capsule{0.25 * size_m, size_m}; break;
    }
    object.reflectance = uniform(generator, 0.2, 0.9);
    result.objects.push_back(std::move(object));
  }
  return result;
}

scene::Scene meshes_and_planes_only(const scene::Scene& scene) {
  scene::Scene result = scene;
  result.objects.clear();
  for (const auto& object : scene.objects) {
    if (std::holds_alternative<scene::Mesh>(object.shape) || std::holds_alternative<scene::Plane>(object.shape)) {
      result.objects.push_back(object);
    }
  }
  return result;
}

scene::Scene corridor_with_cylinder(const scene::Scene& corridor, int triangles) {
  scene::Scene result = corridor;
  if (triangles == 0) return result;
  for (auto& object : result.objects) {
    if (object.name != "cylinder") continue;
    const auto& cylinder = std::get<scene::Cylinder>(object.shape);
    const CylinderResolution resolution = cylinder_resolution_for(triangles);
    object.shape = cylinder_mesh(cylinder.radius_m, cylinder.length_m, resolution.segments, resolution.rings);
  }
  return result;
}

scene::Scene with_effects(scene::Scene scene, const std::vector<scene::Effect>& effects) {
  scene.effects = scene::EffectSet{};
  for (const scene::Effect effect : effects) scene.effects.add(effect);
  return scene;
}

std::vector<scene::Effect> plus(std::vector<scene::Effect> effects, std::initializer_list<scene::Effect> more) {
  effects.insert(effects.end(), more.begin(), more.end());
  return effects;
}

double AngleGrid::angle_rad(int i) const { return (first_deg + step_deg * i) * std::numbers::pi / 180.0; }

std::vector<raycast::Ray> scanner_rays(const scene::ScannerConfig& scanner, const AngleGrid& head,
                                       const AngleGrid& tilt, double max_range_m) {
  std::vector<raycast::Ray> rays;
  rays.reserve(static_cast<std::size_t>(head.count) * static_cast<std::size_t>(tilt.count));
  for (int layer = 0; layer < tilt.count; ++layer) {
    for (int beam = 0; beam < head.count; ++beam) {
      rays.push_back(sensor::beam_ray(scanner, head.angle_rad(beam), tilt.angle_rad(layer), max_range_m));
    }
  }
  return rays;
}

std::vector<raycast::Ray> every_nth(const std::vector<raycast::Ray>& rays, std::size_t stride) {
  std::vector<raycast::Ray> result;
  for (std::size_t i = 0; i < rays.size(); i += stride) result.push_back(rays[i]);
  return result;
}

scene::Scene depth_step_scene(const std::vector<scene::Effect>& effects) {
  scene::Scene step;
  step.source_path = "generated:depth-step";
  step.objects.push_back({"near", scene::Box{Eigen::Vector3d(0.2, 4.0, 4.0)},
                          {Eigen::Vector3d(kDepthStepNear_m + 0.1, 2.0, 0.0), Eigen::Quaterniond::Identity()},
                          kDepthStepNearReflectance, {}, {}});
  step.objects.push_back({"wall", scene::Box{Eigen::Vector3d(0.2, 20.0, 20.0)},
                          {Eigen::Vector3d(kDepthStepWall_m + 0.1, 0.0, 0.0), Eigen::Quaterniond::Identity()},
                          kDepthStepWallReflectance, {}, {}});
  return with_effects(step, effects);
}

}  // namespace ldoem::bench
