// The committed scenes load, and the corridor is the paper's geometry.
#include "ldoem/scene/scene_loader.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "scene_sources.hpp"

namespace ldoem::scene {
namespace {

using test::kScenes;

const SceneObject* find(const Scene& scene, std::string_view name) {
  for (const auto& object : scene.objects) {
    if (object.name == name) return &object;
  }
  return nullptr;
}

TEST(SceneFiles, EveryCommittedScene_Loads) {
  int count = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kScenes)) {
    if (entry.path().extension() != ".yaml") continue;
    const auto result = load_scene(entry.path());
    EXPECT_TRUE(result.has_value()) << (result ? "" : result.error().message());
    ++count;
  }
  EXPECT_GE(count, 9);
}

TEST(SceneFiles, Corridor_IsThePapersExperiment) {
  const auto scene = load_scene(kScenes / "corridor.yaml");
  ASSERT_TRUE(scene) << scene.error().message();
  const SceneObject* wall = find(*scene, "wall");
  const SceneObject* cylinder = find(*scene, "cylinder");
  ASSERT_TRUE(wall && cylinder);
  const auto& wall_box = std::get<Box>(wall->shape);
  const double pivot_x = scene->scanner.pivot_pose.position_m.x();
  EXPECT_NEAR(wall->pose.position_m.x() - wall_box.size_m.x() / 2 - pivot_x, 4.180, 1e-12);
  const auto& cyl = std::get<Cylinder>(cylinder->shape);
  EXPECT_NEAR(2 * cyl.radius_m, 0.195, 1e-12);
  EXPECT_NEAR(cyl.length_m, 0.998, 1e-12);
  EXPECT_NEAR(cylinder->pose.position_m.z() - cyl.length_m / 2, 0.0, 1e-12);  // stands on the floor
  // The whole cylinder is inside the vertical apex of 21.6 deg (+-10.8 deg about level) seen
  // from the optical centre, at its nearest face.
  const Eigen::Vector3d optical = scene->scanner.pivot_pose.position_m + scene->scanner.optical_offset_m;
  const double front_x = cylinder->pose.position_m.x() - cyl.radius_m - optical.x();
  const double half_window = front_x * std::tan(10.8 * M_PI / 180.0);
  EXPECT_LT(optical.z() - half_window, 0.0);
  EXPECT_GT(optical.z() + half_window, cyl.length_m);
  EXPECT_TRUE(scene->effects.has(Effect::noise));
  EXPECT_TRUE(scene->effects.has(Effect::intensity));
  EXPECT_TRUE(scene->effects.has(Effect::incidence));
  EXPECT_EQ(scene->scanner.noise.sigma_m, 0.0015);
}

TEST(SceneFiles, Minimal_HasOneObjectNoEffects) {
  const auto scene = load_scene(kScenes / "minimal.yaml");
  ASSERT_TRUE(scene) << scene.error().message();
  EXPECT_EQ(scene->objects.size(), 1u);
  EXPECT_TRUE(scene->effects.empty());
}

TEST(SceneFiles, Large_Has1000ObjectsAnd100kTriangles) {
  const auto scene = load_scene(kScenes / "large.yaml");
  ASSERT_TRUE(scene) << scene.error().message();
  EXPECT_GE(scene->objects.size(), 1000u);
  const SceneObject* rock = find(*scene, "rock");
  ASSERT_NE(rock, nullptr);
  EXPECT_GE(std::get<Mesh>(rock->shape).triangles.size(), 100000u);
}

}  // namespace
}  // namespace ldoem::scene
