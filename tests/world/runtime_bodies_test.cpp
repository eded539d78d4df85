// D12 runtime changes: a `dynamics` body added through add-object (SceneCaster::add_object) joins
// the running ODE world at its first step not yet computed at or after its device time, falls
// under gravity like a scene body, meets the static world and the other bodies, and is seen by
// rays only from that step on; the same commands give the same ranges, twice.
#include "world_test_support.hpp"

#include <cmath>

namespace ldoem::world {
namespace {

using testing::kG;
using testing::ray_at;
using testing::scene_from;

constexpr double kStep_s = 1e-3;

const std::string kFloor =
    "world: {world_step_s: 0.001}\n"
    "objects:\n"
    "  - plane: {normal: [0, 0, 1], offset_m: 0}\n";

scene::SceneObject falling_ball(const std::string& name, const Eigen::Vector3d& position_m) {
  scene::SceneObject ball;
  ball.name = name;
  ball.shape = scene::Sphere{0.5};
  ball.pose.position_m = position_m;
  scene::Dynamics dynamics;
  dynamics.mass_kg = 2.0;
  dynamics.restitution = 0.0;
  ball.dynamics = dynamics;
  return ball;
}

// The range straight down from 30 m above (x, y), at time t, after readying the casters there.
std::optional<double> range_down(SceneCaster& caster, double x, double y, double t_s) {
  caster.prepare(t_s, t_s + 0.1);
  const auto hit = caster.cast(ray_at(Eigen::Vector3d(x, y, 30.0), -Eigen::Vector3d::UnitZ(), t_s));
  return hit ? std::optional<double>(hit->range_m) : std::nullopt;
}

// Ranges down onto a ball added at 1.0 s, 10 m up, over its fall (before, at its step, falling,
// at rest on the floor). scene_body: the scene has a body of its own elsewhere (otherwise the
// added ball is the world's first body, whose steps start at its time).
std::vector<double> drop_ball(bool scene_body, double at_s, double* joined_s) {
  const std::string extra = scene_body ? "  - name: other\n    box: {size_m: [1, 1, 1]}\n"
                                         "    pose: {position_m: [-5, 0, 0.5]}\n    dynamics: {mass_kg: 3}\n"
                                       : "";
  SceneCaster caster(scene_from(kFloor + extra));
  caster.prepare(at_s - 1.0, at_s - 0.9);
  const auto added = caster.add_object(falling_ball("ball", Eigen::Vector3d(4, 0, 10.5)), at_s);
  EXPECT_TRUE(added.has_value()) << added.error();
  if (!added.has_value()) return {};
  const double t_b = added.value();
  *joined_s = t_b;
  std::vector<double> ranges;
  EXPECT_NEAR(*range_down(caster, 4, 0, t_b - 0.002), 30.0, 1e-9) << "not there before its step: the floor";
  EXPECT_NEAR(*range_down(caster, 4, 0, t_b), 30.0 - 11.0, 1e-9) << "at its pose at its step";
  const double contact_tau = std::sqrt(2.0 * 10.0 / kG);
  for (double tau = 0.0371; tau < contact_tau - 0.05; tau += 0.1137) {
    const double range = *range_down(caster, 4, 0, t_b + tau);
    ranges.push_back(range);
    // The ball's top is at 10.5 + 0.5 - fall; dWorldStep falls ahead of the closed form by at most
    // g h (tau / 2 + h) (docs/dynamic-scenes.md, rigid_bodies_test.cpp).
    const double error = range - (30.0 - (11.0 - 0.5 * kG * tau * tau));
    EXPECT_LE(std::abs(error), kG * kStep_s * (tau / 2.0 + kStep_s) + 1e-9) << "tau " << tau;
  }
  const double rest = *range_down(caster, 4, 0, t_b + contact_tau + 1.5);
  ranges.push_back(rest);
  EXPECT_NEAR(rest, 29.0, 0.02) << "at rest on the floor, top 1 m up";
  return ranges;
}

TEST(RuntimeBodies, AddedBodyJoinsAtItsStepAndFallsLikeASceneBody) {
  // Late in a daemon's life (an hour) only as the world's first body: a scene body would be
  // stepped through the whole hour first.
  for (const auto& [scene_body, at_s] : {std::pair{true, 1.0}, std::pair{false, 1.0}, std::pair{false, 3600.0004}}) {
    double joined_s = 0.0;
    const auto first = drop_ball(scene_body, at_s, &joined_s);
    EXPECT_GE(joined_s, at_s);
    EXPECT_LE(joined_s, at_s + kStep_s * 1.000001) << "the first step not yet computed at or after at_s";
    EXPECT_NEAR(joined_s / kStep_s, std::round(joined_s / kStep_s), 1e-6) << "a step time";
    double again_s = 0.0;
    EXPECT_EQ(first, drop_ball(scene_body, at_s, &again_s)) << "same commands, same ranges (bitwise)";
    EXPECT_EQ(joined_s, again_s);
  }
}

// Steps already computed (the casters step bodies ahead of the beams) are not recomputed: the
// body joins at the first step after them, and the reply says when.
TEST(RuntimeBodies, AddedWhereStepsAreComputedJoinsAfterThem) {
  SceneCaster caster(scene_from(kFloor + "  - name: other\n    sphere: {radius_m: 0.5}\n"
                                         "    pose: {position_m: [-5, 0, 0.5]}\n    dynamics: {mass_kg: 1}\n"));
  caster.prepare(1.0, 1.1);  // steps computed up to 1.3 s (min_window_s)
  const auto added = caster.add_object(falling_ball("ball", Eigen::Vector3d(4, 0, 10.5)), 1.05);
  ASSERT_TRUE(added.has_value());
  EXPECT_GT(added.value(), 1.29);
  EXPECT_LT(added.value(), 1.32);
}

// The added ball lands on a crate of the scene (a body) and rests on it: contacts with the other
// bodies as well as with the static world.
TEST(RuntimeBodies, AddedBodyRestsOnASceneBody) {
  SceneCaster caster(scene_from(kFloor + "  - name: crate\n    box: {size_m: [2, 2, 2]}\n"
                                         "    pose: {position_m: [4, 0, 1]}\n    dynamics: {mass_kg: 50}\n"));
  caster.prepare(0.0, 0.1);
  ASSERT_TRUE(caster.add_object(falling_ball("ball", Eigen::Vector3d(4, 0, 6.5)), 0.5).has_value());
  EXPECT_NEAR(*range_down(caster, 4, 0, 4.0), 30.0 - 3.0, 0.02) << "the ball's top: crate 2 m + ball 1 m";
  EXPECT_NEAR(*range_down(caster, 4.9, 0.9, 4.0), 28.0, 0.02) << "the crate's corner, still on the floor";
}

// A body that does not exist yet cannot be moved; removed before it has joined, it is removed
// when it joins and never seen.
TEST(RuntimeBodies, MoveBeforeItJoinsIsRefusedAndRemoveWaitsForIt) {
  SceneCaster caster(scene_from(kFloor));
  caster.prepare(0.0, 0.1);
  const double t_b = caster.add_object(falling_ball("ball", Eigen::Vector3d(4, 0, 10.5)), 1.0).value();
  const auto early = caster.move_object("ball", scene::Pose{}, 0.5, false);
  ASSERT_TRUE(!early.has_value());
  EXPECT_NE(early.error().find("exists only from"), std::string::npos) << early.error();
  ASSERT_TRUE(caster.remove_object("ball", 1.0).has_value());
  for (const double t : {t_b - 0.01, t_b, t_b + 0.2, t_b + 2.0}) {
    EXPECT_NEAR(*range_down(caster, 4, 0, t), 30.0, 1e-9) << "t " << t;
  }
}

TEST(RuntimeBodies, PlanesAreRefusedWithAReason) {
  SceneCaster caster(scene_from(kFloor));
  scene::SceneObject plane;
  plane.name = "ramp";
  plane.shape = scene::Plane{Eigen::Vector3d(0, 0, 1), 1.0};
  const auto refused = caster.add_object(plane, 0.0);
  ASSERT_TRUE(!refused.has_value());
  EXPECT_NE(refused.error().find("plane"), std::string::npos);
}

}  // namespace
}  // namespace ldoem::world
