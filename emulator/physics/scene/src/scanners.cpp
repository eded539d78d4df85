#include "ldoem/scene/scanners.hpp"

namespace ldoem::scene {

Scene scanner_view(const Scene& scene, std::size_t index) {
  Scene view;
  view.source_path = scene.source_path;
  view.world = scene.world;
  view.seed = scene.seed + index;
  if (scene.scanners.empty()) {
    view.scanner = scene.scanner;
    view.effects = scene.effects;
  } else {
    view.scanner = scene.scanners.at(index).config;
    view.effects = scene.scanners.at(index).effects;
  }
  if (index == 0) view.faults = scene.faults;
  return view;
}

std::string scanner_name(const Scene& scene, std::size_t index) {
  return scene.scanners.empty() ? std::string("scanner") : scene.scanners.at(index).name;
}

std::vector<std::uint32_t> add_housings(Scene& scene) {
  std::vector<std::uint32_t> housings;
  if (scene.scanners.size() < 2) return housings;
  for (const ScannerEntry& entry : scene.scanners) {
    const ScannerConfig& scanner = entry.config;
    SceneObject housing;
    housing.name = "housing:" + entry.name;
    housing.shape = Cylinder{scanner.housing.radius_m, scanner.housing.height_m};
    housing.pose = scanner.pivot_pose;
    housing.reflectance = scanner.housing.reflectance;
    housing.motion = scanner.pivot_motion;  // the housing rides on the scanner's platform (D12)
    housings.push_back(static_cast<std::uint32_t>(scene.objects.size()));
    scene.objects.push_back(std::move(housing));
  }
  return housings;
}

}  // namespace ldoem::scene
