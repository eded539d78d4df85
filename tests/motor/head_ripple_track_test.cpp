// head_dynamics moves the time a point fires, never its angle: the shift is the time the
// rippling head needs to turn as far as the ideal head, counted from the revolution's start.
#include <ldoem/motor/head_ripple_track.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "seconds.hpp"

namespace ldoem::motor {
namespace {

using namespace std::chrono_literals;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// A large ripple: 2 % of 10 Hz at 5 Hz.
scene::HeadConfig large_ripple() {
  scene::HeadConfig head;
  head.ripple_fraction = 0.02;
  head.ripple_frequency_hz = 5.0;
  return head;
}

using test::seconds;

TEST(HeadRippleTrack, WhileSpinningUp_NoShift) {
  HeadRippleTrack track(large_ripple());
  track.set_target(SimTime::zero(), 10.0);
  EXPECT_EQ(track.fire_time_shift(500ms, 3.0), SimTime::zero());  // spin-up takes about 2 s (D7)
}

TEST(HeadRippleTrack, AtTheRevolutionsStart_NoShift) {
  HeadRippleTrack track(large_ripple());
  track.set_target(SimTime::zero(), 10.0);
  EXPECT_EQ(track.fire_time_shift(3300ms, 0.0), SimTime::zero());
}

TEST(HeadRippleTrack, WithoutRipple_NoShiftAnywhere) {
  scene::HeadConfig still;
  still.ripple_fraction = 0.0;
  HeadRippleTrack track(still);
  track.set_target(SimTime::zero(), 10.0);
  for (SimTime start = 3s; start < 4s; start += 100ms) {
    EXPECT_LE(std::abs(track.fire_time_shift(start, 5.0).count()), 1) << start.count();
  }
}

TEST(HeadRippleTrack, HeldSpeed_ShiftIsTheRippleAngleOverTheSpeed) {
  const scene::HeadConfig head = large_ripple();
  HeadRippleTrack track(head);
  track.set_target(SimTime::zero(), 10.0);
  const double omega = kTwoPi * 10.0;
  const SimTime held = *SpinUpCurve(head, SimTime::zero(), 0.0, 0.0, omega).holds_target_from();
  const double angular_frequency = kTwoPi * head.ripple_frequency_hz;
  // The ripple's extra angle since the target was held (DynamicHead's closed form).
  const auto ripple_angle = [&](double since_held_s) {
    return omega * head.ripple_fraction * (1.0 - std::cos(angular_frequency * since_held_s)) / angular_frequency;
  };
  double largest_s = 0.0;
  for (int revolution = 20; revolution < 30; ++revolution) {
    const SimTime start = 2s + revolution * 100ms;
    for (const double angle : {0.5, 2.0, 6.0}) {
      const double shift_s = seconds(track.fire_time_shift(start, angle));
      // Exactly: at its shifted time the rippling head has turned `angle` since the start (to
      // what 1 ns of rounding allows).
      const SimTime fires = start + std::chrono::round<SimTime>(std::chrono::duration<double>(angle / omega)) +
                            track.fire_time_shift(start, angle);
      const HeadDrive& rippling = track.rippling_head();
      EXPECT_NEAR(rippling.angle_rad(fires) - rippling.angle_rad(start), angle, omega * 2e-9);
      // To first order in the ripple fraction: earlier by the ripple angle gained since the start.
      const double nominal_s = seconds(start - held) + angle / omega;
      const double expected_s = -(ripple_angle(nominal_s) - ripple_angle(seconds(start - held))) / omega;
      EXPECT_NEAR(shift_s, expected_s, 2.0 * head.ripple_fraction * std::abs(expected_s) + 2e-9)
          << revolution << " " << angle;
      largest_s = std::max(largest_s, std::abs(shift_s));
    }
  }
  EXPECT_GT(largest_s, 1e-4);  // the ripple is visible: up to 2 A / (Omega omega) = 1.3 ms
  EXPECT_LT(largest_s, 2.0 * head.ripple_fraction / angular_frequency * 1.01);
}

TEST(HeadRippleTrack, FireTime_IsTheNominalTimePlusTheShiftOfItsAngle) {
  HeadRippleTrack track(large_ripple());
  track.set_target(SimTime::zero(), 10.0);
  const SimTime start = 3s;
  for (const SimTime since : {10ms, 40ms, 90ms}) {
    const double angle = 2.0 * std::numbers::pi * 10.0 * seconds(since);
    EXPECT_LE(std::abs((track.fire_time(start, start + since) - (start + since + track.fire_time_shift(start, angle))).count()), 1);
  }
  scene::HeadConfig still;
  still.ripple_fraction = 0.0;
  HeadRippleTrack without(still);
  without.set_target(SimTime::zero(), 10.0);
  EXPECT_LE(std::abs((without.fire_time(start, start + 50ms) - (start + 50ms)).count()), 1);
}

TEST(HeadRippleTrack, NewTarget_BothHeadsFollowIt) {
  HeadRippleTrack track(large_ripple());
  track.set_target(SimTime::zero(), 10.0);
  track.set_target(3s, 0.0);
  EXPECT_EQ(track.fire_time_shift(30s, 1.0), SimTime::zero());  // long stopped
}

}  // namespace
}  // namespace ldoem::motor
