#include "ldoem/scan/profile_points.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ldoem::scan {
namespace {

constexpr double kTolerance = 1e-9;

TEST(PivotPoint, LevelForwardBeam_IsOnPlusX) {
  const Vector3 p = pivot_point(2.0, 0.0, 0.0, {});
  EXPECT_NEAR(p.x, 2.0, kTolerance);
  EXPECT_NEAR(p.y, 0.0, kTolerance);
  EXPECT_NEAR(p.z, 0.0, kTolerance);
}

TEST(PivotPoint, PositiveTilt_RaisesTheForwardBeam) {
  // D5: positive tilt turns the beam plane up.
  const Vector3 p = pivot_point(2.0, 0.0, 30.0, {});
  EXPECT_NEAR(p.x, 2.0 * std::cos(M_PI / 6), kTolerance);
  EXPECT_NEAR(p.z, 2.0 * std::sin(M_PI / 6), kTolerance);
}

TEST(PivotPoint, LeftBeam_IsOnPlusYAndUnaffectedByTilt) {
  const Vector3 p = pivot_point(1.5, 90.0, 10.0, {});
  EXPECT_NEAR(p.x, 0.0, kTolerance);
  EXPECT_NEAR(p.y, 1.5, kTolerance);
  EXPECT_NEAR(p.z, 0.0, kTolerance);
}

TEST(PivotPoint, OpticalOffset_TurnsWithTheTilt) {
  // The offset (0.1, 0, 0.05) at 90 deg tilt: x' = -0.05, z' = 0.1 (+ the beam's own part).
  const Vector3 p = pivot_point(0.0, 0.0, 90.0, {0.1, 0.0, 0.05});
  EXPECT_NEAR(p.x, -0.05, kTolerance);
  EXPECT_NEAR(p.z, 0.1, kTolerance);
}

protocol::Profile one_sector(std::uint16_t start_ticks, std::vector<std::uint16_t> distances) {
  protocol::Profile profile;
  profile.format = protocol::kFormatRangeEcho;
  protocol::SectorBlock block;
  block.dir_step_ticks = 4;
  block.start_dir_ticks = start_ticks;
  for (std::uint16_t d : distances) {
    block.points.push_back({d, 0, static_cast<std::uint16_t>(d / 2)});
  }
  profile.sectors.push_back(block);
  return profile;
}

TEST(BeamAngle, SectorThroughZero_WrapsToNegativeAngles) {
  const protocol::Profile profile = one_sector(5756, {256, 256, 256});
  EXPECT_DOUBLE_EQ(beam_angle_deg(profile.sectors[0], 0, false), -0.25);
  EXPECT_DOUBLE_EQ(beam_angle_deg(profile.sectors[0], 1, false), 0.0);
  EXPECT_DOUBLE_EQ(beam_angle_deg(profile.sectors[0], 2, false), 0.25);
}

TEST(BeamAngle, DirectionField_WinsOverStartAndStep) {
  protocol::SectorBlock block;
  block.start_dir_ticks = 0;
  block.dir_step_ticks = 4;
  block.points.push_back({256, 1440, 0});  // 90 deg
  EXPECT_DOUBLE_EQ(beam_angle_deg(block, 0, true), 90.0);
  EXPECT_DOUBLE_EQ(beam_angle_deg(block, 0, false), 0.0);
}

TEST(ProfileToPoints, NoEcho_IsSkippedButKeepsItsBeamIndex) {
  const protocol::Profile profile = one_sector(0, {512, 0, 768});
  const auto points = profile_to_points(profile, 0.0, {});
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].beam, 0u);
  EXPECT_EQ(points[1].beam, 2u);
  EXPECT_FLOAT_EQ(points[0].position.x_m, 2.0F);
  EXPECT_FLOAT_EQ(points[0].echo, 256.0F);
  const double angle = 0.5 * M_PI / 180.0;
  EXPECT_NEAR(points[1].position.x_m, 3.0 * std::cos(angle), 1e-6);
  EXPECT_NEAR(points[1].position.y_m, 3.0 * std::sin(angle), 1e-6);
}

TEST(ProfileToPoints, EmptySectorBlocks_AddNothing) {
  protocol::Profile profile = one_sector(0, {256});
  profile.sectors.push_back(protocol::SectorBlock{});  // a no-measurement block (D3: POINTNUM 0)
  EXPECT_EQ(profile_to_points(profile, 5.0, {}).size(), 1u);
}

}  // namespace
}  // namespace ldoem::scan
