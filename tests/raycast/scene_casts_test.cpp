// The committed scenes, loaded and cast: the corridor's geometry, the hard cases, the large scene.
#include "caster_fixture.hpp"
#include "ldoem/scene/scene_loader.hpp"

#include <filesystem>

namespace ldoem::raycast {
namespace {

using namespace ldoem::raycast::testing;

const std::filesystem::path kScenes = std::filesystem::path(LDOEM_SOURCE_DIR) / "scenes";

scene::Scene load(const std::string& relative) {
  auto result = scene::load_scene(kScenes / relative);
  EXPECT_TRUE(result.has_value()) << (result ? "" : result.error().message());
  return result ? std::move(result).value() : scene::Scene{};
}

template <class Caster>
class SceneCastTest : public ::testing::Test {};
TYPED_TEST_SUITE(SceneCastTest, CasterTypes);

TYPED_TEST(SceneCastTest, Corridor_LevelBeamHitsCylinderThenWall) {
  Rig<TypeParam> rig(load("corridor.yaml"));
  const Eigen::Vector3d optical = rig.scene.scanner.pivot_pose.position_m + rig.scene.scanner.optical_offset_m;
  const auto cylinder = rig.caster.cast(make_ray(optical, {1, 0, 0}, 30));
  ASSERT_TRUE(cylinder.has_value());
  EXPECT_EQ(rig.scene.objects[cylinder->object_index].name, "cylinder");
  EXPECT_NEAR(cylinder->range_m, 2.9 - 0.0975, 1e-9);
  const auto wall = rig.caster.cast(make_ray(optical, {1, 0.2, 0}, 30));
  ASSERT_TRUE(wall.has_value());
  EXPECT_EQ(rig.scene.objects[wall->object_index].name, "wall");
  EXPECT_NEAR(wall->range_m, 4.18 * std::sqrt(1.04), 1e-9);
  // The cylinder's top (z = 0.998) and foot are inside +-10.8 deg of tilt.
  for (double z : {0.01, 0.99}) {
    const auto hit = rig.caster.cast(make_ray(optical, Eigen::Vector3d(2.8025, 0, z) - optical, 30));
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(rig.scene.objects[hit->object_index].name, "cylinder") << z;
  }
}

TYPED_TEST(SceneCastTest, ScannerInsideBox_SeesTheBoxExit) {
  Rig<TypeParam> rig(load("hard/scanner_inside_box.yaml"));
  const auto hit = rig.caster.cast(make_ray({0, 0, 0}, {1, 0, 0}, 30));
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->object_index, 0u);
  EXPECT_NEAR(hit->range_m, 1.0, 1e-12);
}

TYPED_TEST(SceneCastTest, FarFromOrigin_CylinderAtPaperRange) {
  Rig<TypeParam> rig(load("hard/far_from_origin.yaml"));
  const Eigen::Vector3d optical = rig.scene.scanner.pivot_pose.position_m;
  const auto hit = rig.caster.cast(make_ray(optical, {1, 0, 0}, 30));
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->range_m, 2.9 - 0.0975, 1e-9);
}

TEST(LargeScene, EmbreeBuildsAndAgreesWithOdeOnPrimitives) {
  const scene::Scene s = load("large.yaml");
  const OdeWorld world(s);
  const EmbreeRayCaster fast(world);
  const OdeRayCaster reference(world);
  // Toward the rock (a closed mesh centred at (4, 0, 0.8), radius ~0.8 m).
  const auto rock = fast.cast(make_ray({0, 0, 0.8}, {1, 0, 0}, 30));
  ASSERT_TRUE(rock.has_value());
  EXPECT_EQ(s.objects[rock->object_index].name, "rock");
  EXPECT_NEAR(rock->range_m, 4.0 - 0.8, 0.1);
  // Across the primitive grid, away from the rock: same answers as ODE.
  int compared = 0;
  for (int i = -60; i <= 60; ++i) {
    const Ray ray = make_ray({5.5, 0, 0.3}, {1, 0.03 * i, -0.01}, 30);
    const auto a = reference.cast(ray);
    const auto b = fast.cast(ray);
    ASSERT_EQ(a.has_value(), b.has_value()) << i;
    if (!a) continue;
    EXPECT_EQ(a->object_index, b->object_index) << i;
    EXPECT_NEAR(a->range_m, b->range_m, 1e-9) << i;
    ++compared;
  }
  EXPECT_GT(compared, 100);
}

}  // namespace
}  // namespace ldoem::raycast
