#include <ldoem/motor/head_drive.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "seconds.hpp"

namespace ldoem::motor {
namespace {

using namespace std::chrono_literals;

using test::seconds;

TEST(HeadDrive, DefaultConfig_ReachesTenHertzInAboutTwoSeconds) {
  const scene::HeadConfig config;
  IdealHead ideal(config);
  DynamicHead dynamic(config);
  for (HeadDrive* head : {static_cast<HeadDrive*>(&ideal), static_cast<HeadDrive*>(&dynamic)}) {
    head->set_target(0s, 10.0);
    const std::optional<SimTime> reached = head->reached_at(10.0);
    ASSERT_TRUE(reached) << head->dump();
    EXPECT_GE(seconds(*reached), 1.8);
    EXPECT_LE(seconds(*reached), 2.2);
    EXPECT_NEAR(head->speed_hz(*reached), 10.0, 0.1);         // within 1 % there
    EXPECT_LT(head->speed_hz(*reached - 10ms), 9.9);           // and not before
  }
}

TEST(HeadDrive, SpinUpTime_FromInertiaAndTorque) {
  scene::HeadConfig config;
  config.inertia_kg_m2 = 4.0e-4;  // twice the inertia: twice the time
  IdealHead head(config);
  head.set_target(0s, 10.0);
  const double expected_s = 0.99 * 2 * std::numbers::pi * 10.0 * 4.0e-4 / config.drive_torque_n_m;
  EXPECT_NEAR(seconds(*head.reached_at(10.0)), expected_s, 1e-9);
}

TEST(HeadDrive, SetTargetLater_CountsFromThen) {
  IdealHead head(scene::HeadConfig{});
  head.set_target(5s, 10.0);
  EXPECT_EQ(head.speed_hz(4s), 0.0);
  EXPECT_NEAR(seconds(*head.reached_at(10.0)) - 5.0, 1.975, 0.01);
}

TEST(IdealHead, AtSpeed_NoRipple) {
  IdealHead head(scene::HeadConfig{});
  head.set_target(0s, 10.0);
  for (SimTime at = 3s; at < 4s; at += 37ms) EXPECT_EQ(head.speed_hz(at), 10.0);
}

TEST(DynamicHead, AtSpeed_RipplesByTheConfiguredFraction) {
  scene::HeadConfig config;
  config.ripple_fraction = 0.002;
  config.ripple_frequency_hz = 3.0;
  DynamicHead head(config);
  head.set_target(0s, 10.0);
  double lowest = 100.0;
  double highest = 0.0;
  for (SimTime at = 3s; at < 5s; at += 1ms) {
    lowest = std::min(lowest, head.speed_hz(at));
    highest = std::max(highest, head.speed_hz(at));
  }
  EXPECT_NEAR(highest, 10.0 * 1.002, 1e-4);
  EXPECT_NEAR(lowest, 10.0 * 0.998, 1e-4);
}

TEST(HeadDrive, Angle_IsTheIntegralOfSpeed) {
  scene::HeadConfig config;
  config.ripple_fraction = 0.01;
  config.ripple_frequency_hz = 2.0;
  IdealHead ideal(config);
  DynamicHead dynamic(config);
  for (HeadDrive* head : {static_cast<HeadDrive*>(&ideal), static_cast<HeadDrive*>(&dynamic)}) {
    head->set_target(0s, 10.0);
    double integral = 0.0;
    const SimTime step = 100us;
    for (SimTime at{0}; at < 4s; at += step) {
      integral += 2 * std::numbers::pi * 0.5 * (head->speed_hz(at) + head->speed_hz(at + step)) * seconds(step);
    }
    EXPECT_NEAR(head->angle_rad(4s), integral, 1e-4) << head->dump();
  }
}

TEST(HeadDrive, NewTarget_AngleStaysContinuous) {
  DynamicHead head(scene::HeadConfig{});
  head.set_target(0s, 10.0);
  const double before = head.angle_rad(3s);
  head.set_target(3s, 5.0);
  EXPECT_NEAR(head.angle_rad(3s), before, 1e-9);
  EXPECT_NEAR(head.speed_hz(3s), 10.0, 0.011);  // starts from where it was (ripple aside)
}

TEST(HeadDrive, SpinDown_ReachesZeroAfterTheSameTime) {
  IdealHead head(scene::HeadConfig{});
  head.set_target(0s, 10.0);
  head.set_target(10s, 0.0);
  const std::optional<SimTime> stopped = head.reached_at(0.0);
  ASSERT_TRUE(stopped);
  EXPECT_NEAR(seconds(*stopped) - 10.0, 2 * std::numbers::pi * 10.0 * 2.0e-4 / 6.3e-3, 1e-6);
  EXPECT_EQ(head.speed_hz(20s), 0.0);
}

TEST(HeadDrive, FrictionThatForbidsTheTarget_NeverReached) {
  scene::HeadConfig config;
  config.friction_n_m_s = 1.0e-4;  // terminal speed = T / b = 63 rad/s = 10.03 Hz
  IdealHead head(config);
  head.set_target(0s, 12.0);
  EXPECT_FALSE(head.reached_at(12.0));
  EXPECT_NEAR(head.speed_hz(60s), 6.3e-3 / 1.0e-4 / (2 * std::numbers::pi), 1e-3);
}

TEST(HeadDrive, FrictionSlowsTheSpinUp) {
  scene::HeadConfig config;
  config.friction_n_m_s = 2.0e-5;
  IdealHead with_friction(config);
  IdealHead without(scene::HeadConfig{});
  with_friction.set_target(0s, 10.0);
  without.set_target(0s, 10.0);
  ASSERT_TRUE(with_friction.reached_at(10.0));
  EXPECT_GT(*with_friction.reached_at(10.0), *without.reached_at(10.0));
}

TEST(HeadDrive, OtherSpeedThanTarget_NotReached) {
  IdealHead head(scene::HeadConfig{});
  head.set_target(0s, 5.0);
  EXPECT_FALSE(head.reached_at(10.0));
  EXPECT_TRUE(head.reached_at(4.0));  // passed on the way up
}

TEST(MakeHeadDrive, HeadDynamicsNamed_DynamicElseIdeal) {
  scene::Scene scene;
  EXPECT_NE(dynamic_cast<IdealHead*>(make_head_drive(scene).get()), nullptr);
  scene.effects.add(scene::Effect::head_dynamics);
  EXPECT_NE(dynamic_cast<DynamicHead*>(make_head_drive(scene).get()), nullptr);
}

}  // namespace
}  // namespace ldoem::motor
