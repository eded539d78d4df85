// D12 scene keys: motion, dynamics, pivot_motion, world; their located errors; and the pure
// kinematics (pose_at, path_bounds) the casters rely on.
#include "ldoem/scene/scene_loader.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "scene_sources.hpp"

namespace ldoem::scene {
namespace {

using test::load_ok;

const Eigen::Quaterniond kIdentity = Eigen::Quaterniond::Identity();

TEST(MotionKeys, StaticSceneMovesNothing) {
  const Scene scene = load_ok("objects: [{box: {size_m: [1, 1, 1]}}]");
  EXPECT_FALSE(scene.moves());
  EXPECT_FALSE(scene.objects[0].moves());
}

TEST(MotionKeys, VelocitiesAreReadInSiUnits) {
  const Scene scene = load_ok(
      "objects:\n"
      "  - box: {size_m: [1, 1, 1]}\n"
      "    pose: {position_m: [5, 0, 0]}\n"
      "    motion: {linear_velocity_mps: [-1, 0, 0], angular_velocity_dps: [0, 0, 90]}\n");
  ASSERT_TRUE(scene.moves());
  const auto& velocity = std::get<ConstantVelocity>(*scene.objects[0].motion);
  EXPECT_EQ(velocity.linear_velocity_mps, Eigen::Vector3d(-1, 0, 0));
  EXPECT_NEAR(velocity.angular_velocity_rad_s.z(), std::numbers::pi / 2, 1e-15);
  const Pose later = pose_at(*scene.objects[0].motion, scene.objects[0].pose, 2.0);
  EXPECT_NEAR((later.position_m - Eigen::Vector3d(3, 0, 0)).norm(), 0.0, 1e-15);
  // 90 deg/s for 2 s: a half turn about z maps +x to -x.
  EXPECT_NEAR((later.orientation * Eigen::Vector3d::UnitX() - Eigen::Vector3d(-1, 0, 0)).norm(), 0.0, 1e-12);
}

TEST(MotionKeys, WaypointsSetThePoseAndInterpolate) {
  const Scene scene = load_ok(
      "objects:\n"
      "  - sphere: {radius_m: 0.5}\n"
      "    motion:\n"
      "      interpolation: cubic\n"
      "      loop: true\n"
      "      waypoints:\n"
      "        - {t_s: 0, position_m: [0, 0, 0]}\n"
      "        - {t_s: 1, position_m: [1, 2, 0], rpy_deg: [0, 0, 90]}\n"
      "        - {t_s: 3, position_m: [0, 0, 0]}\n");
  const SceneObject& object = scene.objects[0];
  const auto& path = std::get<Waypoints>(*object.motion);
  EXPECT_EQ(path.interpolation, Interpolation::cubic);
  EXPECT_TRUE(path.loop);
  EXPECT_EQ(object.pose.position_m, Eigen::Vector3d::Zero());
  for (const Waypoint& w : path.points) {
    EXPECT_NEAR((pose_at(*object.motion, object.pose, w.t_s).position_m - w.position_m).norm(), 0.0, 1e-12);
  }
  // Looped: t = 4 is t = 1 again.
  EXPECT_NEAR((pose_at(*object.motion, object.pose, 4.0).position_m - Eigen::Vector3d(1, 2, 0)).norm(), 0.0, 1e-12);
  EXPECT_FALSE(keeps_orientation(*object.motion));
}

TEST(MotionKeys, LinearWaypointsHoldTheirEnds) {
  Waypoints path;
  path.points = {{1.0, Eigen::Vector3d(0, 0, 0), kIdentity}, {2.0, Eigen::Vector3d(2, 0, 0), kIdentity}};
  const Motion motion = path;
  EXPECT_EQ(pose_at(motion, {}, 0.0).position_m, Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(pose_at(motion, {}, 1.5).position_m, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(pose_at(motion, {}, 9.0).position_m, Eigen::Vector3d(2, 0, 0));
  EXPECT_TRUE(keeps_orientation(motion));
}

// Every sampled position of a path over a window lies inside path_bounds of that window.
TEST(MotionKeys, PathBoundsHoldEverySampledPosition) {
  Waypoints cubic;
  cubic.interpolation = Interpolation::cubic;
  cubic.loop = true;
  cubic.points = {{0.0, Eigen::Vector3d(0, 0, 0), kIdentity},
                  {0.3, Eigen::Vector3d(1, 3, -1), kIdentity},
                  {0.5, Eigen::Vector3d(-2, 1, 0), kIdentity},
                  {1.1, Eigen::Vector3d(0, 0, 2), kIdentity}};
  Waypoints linear = cubic;
  linear.interpolation = Interpolation::linear;
  linear.loop = false;
  const Motion motions[] = {cubic, linear, ConstantVelocity{Eigen::Vector3d(1, -2, 3), Eigen::Vector3d(0, 1, 0)}};
  for (const Motion& motion : motions) {
    for (double t0 = -0.5; t0 < 3.0; t0 += 0.137) {
      for (double span : {0.01, 0.1, 0.7, 2.5}) {
        const PathBounds bounds = path_bounds(motion, {}, t0, t0 + span);
        for (int k = 0; k <= 50; ++k) {
          const Eigen::Vector3d p = pose_at(motion, {}, t0 + span * k / 50.0).position_m;
          ASSERT_TRUE((p.array() >= bounds.lower_m.array() - 1e-12).all() &&
                      (p.array() <= bounds.upper_m.array() + 1e-12).all())
              << "t0 " << t0 << " span " << span << " k " << k;
        }
      }
    }
  }
}

TEST(MotionKeys, DynamicsPivotMotionAndWorld) {
  const Scene scene = load_ok(
      "world: {gravity_mps2: [0, 0, -9.8], world_step_s: 0.0005, beam_time: per_revolution}\n"
      "scanner:\n"
      "  pivot_motion: {linear_velocity_mps: [0.5, 0, 0]}\n"
      "objects:\n"
      "  - sphere: {radius_m: 0.2}\n"
      "    dynamics: {mass_kg: 3, initial_velocity_mps: [1, 0, 0], friction: 0.5, restitution: 0.1}\n"
      "  - box: {size_m: [1, 1, 1]}\n"
      "    dynamics: {density_kg_m3: 300}\n");
  EXPECT_TRUE(scene.moves());
  EXPECT_TRUE(scene.scanner.pivot_motion.has_value());
  EXPECT_EQ(scene.world.world_step_s, 0.0005);
  EXPECT_EQ(scene.world.beam_time, BeamTime::per_revolution);
  EXPECT_EQ(scene.objects[0].dynamics->mass_kg, 3.0);
  EXPECT_EQ(scene.objects[0].dynamics->restitution, 0.1);
  EXPECT_FALSE(scene.objects[1].dynamics->mass_kg.has_value());
  EXPECT_EQ(scene.objects[1].dynamics->density_kg_m3, 300.0);
}

struct BadMotion {
  const char* title;
  const char* yaml;
  SceneErrorKind kind;
  const char* key_path;
  int line;
};

const BadMotion kBadMotions[] = {
    {"absurd speed", "objects:\n  - box: {size_m: [1, 1, 1]}\n    motion: {linear_velocity_mps: [2000, 0, 0]}",
     SceneErrorKind::out_of_range, "objects[0].motion.linear_velocity_mps", 3},
    {"absurd spin", "objects:\n  - box: {size_m: [1, 1, 1]}\n    motion: {angular_velocity_dps: [0, 0, 1e6]}",
     SceneErrorKind::out_of_range, "objects[0].motion.angular_velocity_dps", 3},
    {"absurd initial velocity", "objects:\n  - sphere: {radius_m: 1}\n    dynamics: {initial_velocity_mps: [0, 0, 1e5]}",
     SceneErrorKind::out_of_range, "objects[0].dynamics.initial_velocity_mps", 3},
    {"absurd pivot speed", "scanner:\n  pivot_motion: {linear_velocity_mps: [0, 1e4, 0]}", SceneErrorKind::out_of_range,
     "scanner.pivot_motion.linear_velocity_mps", 2},
    {"repeated waypoint time",
     "objects:\n  - box: {size_m: [1, 1, 1]}\n    motion:\n      waypoints:\n        - {t_s: 1, position_m: [0, 0, 0]}\n"
     "        - {t_s: 1, position_m: [1, 0, 0]}",
     SceneErrorKind::out_of_range, "objects[0].motion.waypoints[1].t_s", 6},
    {"decreasing waypoint time",
     "objects:\n  - box: {size_m: [1, 1, 1]}\n    motion:\n      waypoints:\n        - {t_s: 2, position_m: [0, 0, 0]}\n"
     "        - {t_s: 3, position_m: [1, 0, 0]}\n        - {t_s: 2.5, position_m: [2, 0, 0]}",
     SceneErrorKind::out_of_range, "objects[0].motion.waypoints[2].t_s", 7},
    {"waypoints too fast",
     "objects:\n  - box: {size_m: [1, 1, 1]}\n    motion:\n      waypoints:\n        - {t_s: 0, position_m: [0, 0, 0]}\n"
     "        - {t_s: 0.001, position_m: [100, 0, 0]}",
     SceneErrorKind::out_of_range, "objects[0].motion.waypoints[1]", 6},
    {"one waypoint", "objects:\n  - box: {size_m: [1, 1, 1]}\n    motion: {waypoints: [{t_s: 0, position_m: [0, 0, 0]}]}",
     SceneErrorKind::out_of_range, "objects[0].motion.waypoints", 3},
    {"waypoints and pose",
     "objects:\n  - box: {size_m: [1, 1, 1]}\n    pose: {position_m: [1, 0, 0]}\n"
     "    motion: {waypoints: [{t_s: 0, position_m: [0, 0, 0]}, {t_s: 1, position_m: [1, 0, 0]}]}",
     SceneErrorKind::conflicting_keys, "objects[0].pose", 3},
    {"velocities and waypoints",
     "objects:\n  - box: {size_m: [1, 1, 1]}\n"
     "    motion: {linear_velocity_mps: [1, 0, 0], waypoints: [{t_s: 0, position_m: [0, 0, 0]}]}",
     SceneErrorKind::conflicting_keys, "objects[0].motion.waypoints", 3},
    {"empty motion", "objects:\n  - box: {size_m: [1, 1, 1]}\n    motion: {}", SceneErrorKind::missing_key,
     "objects[0].motion", 3},
    {"bad interpolation",
     "objects:\n  - box: {size_m: [1, 1, 1]}\n    motion:\n      interpolation: spline\n"
     "      waypoints: [{t_s: 0, position_m: [0, 0, 0]}, {t_s: 1, position_m: [1, 0, 0]}]",
     SceneErrorKind::out_of_range, "objects[0].motion.interpolation", 4},
    {"loop not a bool",
     "objects:\n  - box: {size_m: [1, 1, 1]}\n    motion:\n      loop: often\n"
     "      waypoints: [{t_s: 0, position_m: [0, 0, 0]}, {t_s: 1, position_m: [1, 0, 0]}]",
     SceneErrorKind::wrong_type, "objects[0].motion.loop", 4},
    {"motion and dynamics",
     "objects:\n  - sphere: {radius_m: 1}\n    motion: {linear_velocity_mps: [1, 0, 0]}\n    dynamics: {mass_kg: 1}",
     SceneErrorKind::conflicting_keys, "objects[0].dynamics", 2},
    {"moving plane", "objects:\n  - plane: {normal: [0, 0, 1]}\n    motion: {linear_velocity_mps: [1, 0, 0]}",
     SceneErrorKind::conflicting_keys, "objects[0].motion", 3},
    {"mass and density", "objects:\n  - sphere: {radius_m: 1}\n    dynamics: {mass_kg: 1, density_kg_m3: 2}",
     SceneErrorKind::conflicting_keys, "objects[0].dynamics.density_kg_m3", 3},
    {"negative mass", "objects:\n  - sphere: {radius_m: 1}\n    dynamics: {mass_kg: -1}", SceneErrorKind::out_of_range,
     "objects[0].dynamics.mass_kg", 3},
    {"restitution above one", "objects:\n  - sphere: {radius_m: 1}\n    dynamics: {restitution: 1.5}",
     SceneErrorKind::out_of_range, "objects[0].dynamics.restitution", 3},
    {"unknown dynamics key", "objects:\n  - sphere: {radius_m: 1}\n    dynamics: {mas_kg: 1}", SceneErrorKind::unknown_key,
     "objects[0].dynamics.mas_kg", 3},
    {"world step too coarse", "world:\n  world_step_s: 0.5", SceneErrorKind::out_of_range, "world.world_step_s", 2},
    {"bad beam_time", "world:\n  beam_time: sometimes", SceneErrorKind::out_of_range, "world.beam_time", 2},
    {"pivot waypoints and pivot pose",
     "scanner:\n  pivot_pose: {position_m: [0, 0, 1]}\n"
     "  pivot_motion: {waypoints: [{t_s: 0, position_m: [0, 0, 0]}, {t_s: 1, position_m: [1, 0, 0]}]}",
     SceneErrorKind::conflicting_keys, "scanner.pivot_pose", 2},
};

class BadMotionTest : public ::testing::TestWithParam<BadMotion> {};

TEST_P(BadMotionTest, GivesALocatedError) {
  const BadMotion& bad = GetParam();
  const auto scene = load_scene_from_string(bad.yaml, "bad.yaml");
  ASSERT_FALSE(scene.has_value()) << bad.title;
  EXPECT_EQ(scene.error().kind, bad.kind) << bad.title << ": " << scene.error().message();
  EXPECT_EQ(scene.error().key_path, bad.key_path) << bad.title << ": " << scene.error().message();
  EXPECT_EQ(scene.error().line, bad.line) << bad.title << ": " << scene.error().message();
}

INSTANTIATE_TEST_SUITE_P(Scenes, BadMotionTest, ::testing::ValuesIn(kBadMotions));

}  // namespace
}  // namespace ldoem::scene
