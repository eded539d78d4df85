// D12 dynamics on ODE: free fall against the closed form (within the documented step error),
// contact, tunnelling, leaving the world, resting without drift, control-socket moves.
#include "world_test_support.hpp"

#include <cmath>

namespace ldoem::world {
namespace {

using testing::kG;
using testing::ray_at;
using testing::scene_from;

// dWorldStep integrates velocity first (semi-implicit Euler): after n steps of h the fall is
// g h^2 n (n + 1) / 2, i.e. g t^2 / 2 + g h t / 2. Interpolating between steps adds at most
// g h^2 / 8. docs/dynamic-scenes.md states the bound g h (t / 2 + h).
TEST(RigidBodies, FallingSphereFollowsFreeFallUntilContact) {
  for (const double step : {1e-2, 1e-3, 1e-4}) {
    const scene::Scene scene = scene_from(
        "world: {world_step_s: " + std::to_string(step) + "}\n"
        "objects:\n"
        "  - plane: {normal: [0, 0, 1], offset_m: 0}\n"
        "  - name: ball\n"
        "    sphere: {radius_m: 0.5}\n"
        "    pose: {position_m: [0, 0, 20.5]}\n"
        "    dynamics: {mass_kg: 2, restitution: 0}\n");
    RigidBodies bodies(scene);
    ASSERT_EQ(bodies.body_count(), 1u);
    const double contact_s = std::sqrt(2.0 * 20.0 / kG);  // about 2.02 s
    bodies.advance(0.0, contact_s - 0.05);
    for (double t = 0.0137; t < contact_s - 0.05; t += 0.0931) {
      const double expected = 20.5 - 0.5 * kG * t * t;
      const double error = expected - bodies.pose_at(0, t).position_m.z();
      EXPECT_LE(std::abs(error), kG * step * (t / 2.0 + step)) << "step " << step << " t " << t;
      EXPECT_GE(error, -1e-12) << "Euler falls ahead of the closed form, never behind";
    }
    // After contact the ball comes to rest on the floor.
    bodies.advance(0.0, contact_s + 2.0);
    const double z = bodies.pose_at(0, contact_s + 2.0).position_m.z();
    EXPECT_NEAR(z, 0.5, 0.02) << "step " << step;
  }
}

// A body meeting a static object that is not the scene's first: the obstacle's ODE geom carries
// its object index, which the contact callback once read as a material pointer (a crash).
TEST(RigidBodies, BodyLandsOnAStaticObjectAfterTheFirst) {
  const scene::Scene scene = scene_from(
      "objects:\n"
      "  - name: wall\n    box: {size_m: [0.2, 4, 2]}\n    pose: {position_m: [10, 0, 1]}\n"
      "  - name: pillar\n    box: {size_m: [1, 1, 1]}\n    pose: {position_m: [0, 5, 0.5]}\n"
      "  - plane: {normal: [0, 0, 1], offset_m: 0}\n"
      "  - name: ball\n    sphere: {radius_m: 0.5}\n    pose: {position_m: [0, 0, 2.5]}\n"
      "    dynamics: {mass_kg: 1, restitution: 0}\n"
      "  - name: crate\n    box: {size_m: [0.4, 0.4, 0.4]}\n    pose: {position_m: [0, 5, 2]}\n"
      "    dynamics: {mass_kg: 1, restitution: 0}\n");
  RigidBodies bodies(scene);
  bodies.advance(0.0, 3.0);
  EXPECT_NEAR(bodies.pose_at(0, 3.0).position_m.z(), 0.5, 0.02) << "on the floor (object 2)";
  EXPECT_NEAR(bodies.pose_at(1, 3.0).position_m.z(), 1.2, 0.02) << "on the pillar (object 1)";
}

TEST(RigidBodies, FastSmallBodyDoesNotTunnelThroughAThinWall) {
  const scene::Scene scene = scene_from(
      "world: {gravity_mps2: [0, 0, 0], world_step_s: 0.001}\n"
      "objects:\n"
      "  - box: {size_m: [0.005, 4, 4]}\n"
      "    pose: {position_m: [1, 0, 0]}\n"
      "  - sphere: {radius_m: 0.01}\n"
      "    dynamics: {mass_kg: 0.01, initial_velocity_mps: [300, 0, 0], restitution: 0}\n");
  RigidBodies bodies(scene);
  bodies.advance(0.0, 0.1);  // 30 m of flight if nothing stopped it
  EXPECT_LT(bodies.pose_at(0, 0.1).position_m.x(), 1.0);
}

TEST(RigidBodies, BodyLeavingTheWorldIsFrozenAndHarmless) {
  const scene::Scene scene = scene_from(
      "world: {world_step_s: 0.01}\n"
      "objects:\n"
      "  - sphere: {radius_m: 0.2}\n"
      "    dynamics: {initial_velocity_mps: [0, 0, -900]}\n");
  RigidBodies bodies(scene);
  bodies.advance(0.0, 30.0);
  EXPECT_TRUE(bodies.left_world(0));
  const Eigen::Vector3d p = bodies.pose_at(0, 30.0).position_m;
  EXPECT_TRUE(p.allFinite());
  EXPECT_LE(p.cwiseAbs().maxCoeff(), kWorldLimit_m);
  // And no ray finds it any more.
  SceneCaster caster(scene);
  caster.prepare(29.0, 30.0);
  EXPECT_FALSE(caster.cast(ray_at(Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitZ(), 29.5)));
}

TEST(RigidBodies, BodyRestingOnTheFloorStaysPutFor1e5Steps) {
  const scene::Scene scene = scene_from(
      "world: {world_step_s: 0.001}\n"
      "objects:\n"
      "  - plane: {normal: [0, 0, 1], offset_m: 0}\n"
      "  - box: {size_m: [0.6, 0.4, 0.3]}\n"
      "    pose: {position_m: [1, 2, 0.15], rpy_deg: [0, 0, 30]}\n"
      "    dynamics: {mass_kg: 5}\n");
  RigidBodies bodies(scene);
  bodies.advance(0.0, 1.0);
  const scene::Pose settled = bodies.pose_at(0, 1.0);
  EXPECT_NEAR(settled.position_m.z(), 0.15, 1e-3);
  bodies.advance(99.0, 100.0);
  EXPECT_GE(bodies.steps_taken(), 100000u);
  const scene::Pose later = bodies.pose_at(0, 100.0);
  EXPECT_LT((later.position_m - settled.position_m).norm(), 1e-6);
  EXPECT_LT(later.orientation.angularDistance(settled.orientation), 1e-6);
}

TEST(RigidBodies, RollingBallKeepsRollingAndCratesStack) {
  const scene::Scene scene = scene_from(
      "objects:\n"
      "  - plane: {normal: [0, 0, 1], offset_m: 0}\n"
      "  - sphere: {radius_m: 0.2}\n"
      "    pose: {position_m: [0, 0, 0.2]}\n"
      "    dynamics: {mass_kg: 1, initial_velocity_mps: [2, 0, 0]}\n"
      "  - box: {size_m: [1, 1, 1]}\n"
      "    pose: {position_m: [0, 5, 0.5]}\n"
      "    dynamics: {mass_kg: 10}\n"
      "  - box: {size_m: [0.5, 0.5, 0.5]}\n"
      "    pose: {position_m: [0, 5, 3]}\n"
      "    dynamics: {mass_kg: 2}\n");
  RigidBodies bodies(scene);
  bodies.advance(0.0, 2.0);
  EXPECT_GT(bodies.pose_at(0, 2.0).position_m.x(), 1.5);               // rolled on
  EXPECT_NEAR(bodies.pose_at(0, 2.0).position_m.z(), 0.2, 0.01);      // on the floor
  EXPECT_NEAR(bodies.pose_at(2, 2.0).position_m.z(), 1.25, 0.02);      // on top of the big crate
}

TEST(RigidBodies, PoseAtInterpolatesBetweenSteps) {
  const scene::Scene scene = scene_from(
      "world: {gravity_mps2: [0, 0, 0], world_step_s: 0.01}\n"
      "objects:\n"
      "  - sphere: {radius_m: 0.2}\n"
      "    dynamics: {initial_velocity_mps: [1, 0, 0]}\n");
  RigidBodies bodies(scene);
  bodies.advance(0.0, 1.0);
  EXPECT_NEAR(bodies.pose_at(0, 0.505).position_m.x(), 0.505, 1e-12);
  for (const double t : {0.0, 0.3, 0.505, 0.77777, 1.0, 2.0}) {
    EXPECT_EQ(bodies.position_at(0, t), bodies.pose_at(0, t).position_m) << "the same numbers, t " << t;
  }
  const scene::PathBounds b = bodies.origin_bounds(0, 0.2, 0.3);
  EXPECT_LE(b.lower_m.x(), 0.2 + 1e-12);
  EXPECT_GE(b.upper_m.x(), 0.3 - 1e-12);
}

TEST(WorldMotion, MoveObjectAtADeviceTime) {
  const scene::Scene scene = scene_from(
      "world: {world_step_s: 0.001}\n"
      "objects:\n"
      "  - plane: {normal: [0, 0, 1], offset_m: 0}\n"
      "  - name: person\n"
      "    box: {size_m: [0.5, 0.3, 1.8]}\n"
      "    pose: {position_m: [5, 0, 0.9]}\n"
      "    motion: {linear_velocity_mps: [0, 1, 0]}\n"
      "  - name: crate\n"
      "    box: {size_m: [0.5, 0.5, 0.5]}\n"
      "    pose: {position_m: [3, 0, 0.25]}\n"
      "    dynamics: {mass_kg: 5}\n"
      "  - name: pillar\n"
      "    box: {size_m: [0.5, 0.5, 3]}\n"
      "    pose: {position_m: [8, 0, 1.5]}\n");
  SceneCaster caster(scene);
  scene::Pose there;
  there.position_m = Eigen::Vector3d(4, 0, 0.9);
  ASSERT_FALSE(caster.motion().move_object("person", there, 2.0));
  scene::Pose lifted;
  lifted.position_m = Eigen::Vector3d(3, 0, 5);
  ASSERT_FALSE(caster.motion().move_object("crate", lifted, 1.0));
  EXPECT_TRUE(caster.motion().move_object("pillar", there, 1.0)) << "static objects are not movable";
  EXPECT_TRUE(caster.motion().move_object("nobody", there, 1.0));
  scene::Pose far = there;
  far.position_m.x() = 1e7;
  EXPECT_TRUE(caster.motion().move_object("person", far, 1.0));

  caster.prepare(1.9, 2.1);
  // A move made after that window was prepared is seen at the next prepare, even inside it.
  const auto before = caster.cast(ray_at(Eigen::Vector3d(0, 3, 0.9), Eigen::Vector3d::UnitX(), 2.05));
  scene::Pose across;
  across.position_m = Eigen::Vector3d(2, 3, 0.9);
  ASSERT_FALSE(caster.motion().move_object("person", across, 2.06));
  caster.prepare(2.06, 2.1);
  const auto after = caster.cast(ray_at(Eigen::Vector3d(0, 3, 0.9), Eigen::Vector3d::UnitX(), 2.07));
  ASSERT_TRUE(after);
  EXPECT_NEAR(after->range_m, 1.75, 1e-9);
  EXPECT_TRUE(!before || before->range_m > 1.75);
  const std::size_t person = 0;  // moving index (scene order)
  EXPECT_NEAR(caster.motion().pose_at(person, 1.9).position_m.y(), 1.9, 1e-12);
  EXPECT_EQ(caster.motion().pose_at(person, 2.05).position_m, there.position_m);
  const auto hit = caster.cast(ray_at(Eigen::Vector3d(0, 0, 0.9), Eigen::Vector3d::UnitX(), 2.05));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 3.75, 1e-9);  // the crate was lifted away at 1 s: the person is first
  EXPECT_EQ(hit->object_index, 1u);
}

// move-object on a body is a teleport: by default it restarts from rest at the new pose; with
// keep_velocity it carries on with the velocity it had at that step. Both fall under gravity.
TEST(RigidBodies, PlaceTeleportsAtRestOrKeepingTheVelocity) {
  const std::string text = "world: {world_step_s: 0.001}\n"
                           "objects:\n"
                           "  - name: ball\n"
                           "    sphere: {radius_m: 0.1}\n"
                           "    pose: {position_m: [0, 0, 500]}\n"
                           "    dynamics: {mass_kg: 1, initial_velocity_mps: [2, 0, 0]}\n";
  scene::Pose up;
  up.position_m = Eigen::Vector3d(0, 0, 1000);
  for (const bool keep : {false, true}) {
    RigidBodies bodies(scene_from(text));
    bodies.advance(0.0, 0.5);  // steps up to 0.5 s are taken: a move at 0.2 s waits for the next step
    const double late = bodies.place(0, up, 0.2, keep);
    EXPECT_NEAR(late, 0.501, 1e-12) << "the first step not yet computed";
    const double on_time = bodies.place(0, up, 0.75, keep);
    EXPECT_NEAR(on_time, 0.75, 1e-12);
    bodies.advance(0.0, 1.0);
    const scene::Pose at = bodies.pose_at(0, 1.0);
    const double dt = 1.0 - 0.75;
    if (keep) {
      // It keeps the 2 m/s sideways and the downward speed gathered since t = 0 (both moves kept
      // it: g * 0.75 s at the second one).
      EXPECT_NEAR(at.position_m.x(), 2.0 * dt, 0.01);
      EXPECT_NEAR(1000.0 - at.position_m.z(), kG * 0.75 * dt + 0.5 * kG * dt * dt, 0.02);
    } else {
      EXPECT_NEAR(at.position_m.x(), 0.0, 1e-12);
      EXPECT_NEAR(1000.0 - at.position_m.z(), 0.5 * kG * dt * dt, 0.01);
    }
  }
}

}  // namespace
}  // namespace ldoem::world
