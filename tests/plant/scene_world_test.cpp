// Effects on demand (D12): a scene in which nothing moves, without a control socket, builds none
// of the motion machinery: EmbreeRayCaster alone, no timing for the measurements, no moving
// objects. Something that moves, or --control (an editable world), builds world::SceneCaster.
#include <gtest/gtest.h>

#include "ldoem/plant/scene_plant.hpp"
#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/scene/scene_loader.hpp"
#include "ldoem/world/scene_caster.hpp"

namespace ldoem::plant {
namespace {

scene::Scene scene_from(const std::string& yaml) {
  auto scene = scene::load_scene_from_string(yaml, "test.yaml");
  EXPECT_TRUE(scene) << (scene ? "" : scene.error().message());
  return scene ? *scene : scene::Scene{};
}

const std::string kWall = "objects:\n  - name: wall\n    box: {size_m: [0.2, 20, 6]}\n    pose: {position_m: [5.1, 0, 0]}\n";

TEST(SceneWorld, StaticSceneWithoutControl_BuildsNoMotionMachinery) {
  SceneWorld world(scene_from(kWall));
  EXPECT_NE(dynamic_cast<const raycast::EmbreeRayCaster*>(&world.caster()), nullptr);
  EXPECT_EQ(dynamic_cast<const world::SceneCaster*>(&world.caster()), nullptr);
  EXPECT_FALSE(world.timing()) << "no prepare per revolution";
  EXPECT_EQ(world.motion(), nullptr);
  EXPECT_TRUE(!world.add_object(scene::SceneObject{}, 1.0).has_value()) << "not editable";
}

TEST(SceneWorld, MovingSceneOrControl_BuildsTheSceneCaster) {
  const std::string walker = kWall + "  - name: walker\n    sphere: {radius_m: 0.3}\n"
                                     "    motion: {linear_velocity_mps: [0, 1, 0]}\n";
  for (const auto& [yaml, editable] : {std::pair{walker, false}, std::pair{kWall, true}}) {
    SceneWorld world(scene_from(yaml), editable);
    EXPECT_NE(dynamic_cast<const world::SceneCaster*>(&world.caster()), nullptr);
    EXPECT_TRUE(world.timing());
    EXPECT_NE(world.motion(), nullptr);
  }
}

}  // namespace
}  // namespace ldoem::plant
