// Issue 15: a ray passes through its Ray::ignored_object (a scanner's own housing) and sees
// everything else as before, in both casters.
#include "caster_fixture.hpp"

namespace ldoem::raycast::testing {
namespace {

template <class Caster>
class IgnoredObject : public ::testing::Test {};
TYPED_TEST_SUITE(IgnoredObject, CasterTypes);


// A housing cylinder about the origin, a second 3 m ahead, a wall 6 m ahead, a floor plane.
template <class Caster>
std::unique_ptr<Rig<Caster>> two_housings() {
  std::vector<scene::SceneObject> objects{
      make_object(scene::Cylinder{0.06, 0.16}, {0, 0, 0}),
      make_object(scene::Cylinder{0.06, 0.16}, {3, 0, 0}),
      make_object(scene::Box{{0.2, 10, 3}}, {6.1, 0, 0}),
  };
  objects.push_back(make_object(scene::Plane{{0, 0, 1}, -1.0}, {0, 0, 0}));
  return rig_of<Caster>(std::move(objects));
}

TYPED_TEST(IgnoredObject, TheOwnHousingIsPassedTheOtherIsHit) {
  auto rig = two_housings<TypeParam>();
  Ray ray = make_ray({0, 0, 0}, {1, 0, 0});
  const auto inside = rig->caster.cast(ray);  // from inside the own housing: its wall
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->object_index, 0u);
  EXPECT_NEAR(inside->range_m, 0.06, 1e-9);

  ray.ignored_object = 0;
  const auto past = rig->caster.cast(ray);
  ASSERT_TRUE(past);
  EXPECT_EQ(past->object_index, 1u);
  EXPECT_NEAR(past->range_m, 3.0 - 0.06, 1e-9);

  ray.ignored_object = 1;  // ignoring the other one instead: the own wall again
  EXPECT_EQ(rig->caster.cast(ray)->object_index, 0u);

  Ray both = make_ray({0, 0, 0}, {1, 0, 0});
  both.ignored_object = 0;
  both.origin_m = {3.5, 0, 0};  // beyond the second housing: the wall
  const auto wall = rig->caster.cast(both);
  ASSERT_TRUE(wall);
  EXPECT_EQ(wall->object_index, 2u);
  EXPECT_NEAR(wall->range_m, 2.5, 1e-9);
}

TYPED_TEST(IgnoredObject, AnIndexBeyondTheSceneChangesNothing) {
  auto rig = two_housings<TypeParam>();
  Ray ray = make_ray({0.5, 0, 0}, {1, 0, 0});
  const auto plain = rig->caster.cast(ray);
  ray.ignored_object = 1000;
  const auto ignored = rig->caster.cast(ray);
  ASSERT_TRUE(plain && ignored);
  EXPECT_EQ(plain->object_index, ignored->object_index);
  EXPECT_EQ(plain->range_m, ignored->range_m);
}

}  // namespace
}  // namespace ldoem::raycast::testing
