// Issue 15: in a world that moves (D12), a ray passes through its ignored object whether that
// object moves (a housing on a moving platform) or stands still (the SceneCaster's static part
// numbers its objects differently from the scene).
#include "world_test_support.hpp"

namespace ldoem::world::testing {
namespace {

const char* const kScene = R"(
objects:
  - {name: still_wall, box: {size_m: [0.2, 10, 3]}, pose: {position_m: [6.1, 0, 0]}}
  - {name: still_housing, cylinder: {radius_m: 0.06, length_m: 0.16}, pose: {position_m: [0, 0, 0]}}
  - {name: moving_housing, cylinder: {radius_m: 0.06, length_m: 0.16}, pose: {position_m: [3, 0, 0]},
     motion: {linear_velocity_mps: [0, 0.5, 0]}}
)";

TEST(IgnoredObject, StaticAndMovingObjectsArePassedInAMovingWorld) {
  const scene::Scene scene = scene_from(kScene);
  SceneCaster caster(scene);
  caster.prepare(0.0, 0.1);
  raycast::Ray ray = ray_at({0, 0, 0}, {1, 0, 0}, 0.0);
  EXPECT_EQ(caster.cast(ray)->object_index, 1u);  // from inside the still housing
  ray.ignored_object = 1;
  const auto moving = caster.cast(ray);
  ASSERT_TRUE(moving);
  EXPECT_EQ(moving->object_index, 2u);
  EXPECT_NEAR(moving->range_m, 2.94, 1e-9);
  ray.origin_m = {2.0, 0, 0};
  ray.ignored_object = 2;
  const auto wall = caster.cast(ray);
  ASSERT_TRUE(wall);
  EXPECT_EQ(wall->object_index, 0u);
  EXPECT_NEAR(wall->range_m, 4.0, 1e-9);
}

}  // namespace
}  // namespace ldoem::world::testing
