// Per-beam time against closed forms: an approaching wall, a spinning box, a platform moving
// towards a wall. Every index option and the unprepared path must give the same exact ranges.
#include "ldoem/sensor/sensor_model.hpp"
#include "world_test_support.hpp"

#include <cmath>
#include <numbers>

namespace ldoem::world {
namespace {

using testing::kIndexOptions;
using testing::ray_at;
using testing::scene_from;

constexpr double kWallStart_m = 10.0;  // the wall's near face at t = 0
constexpr double kWallSpeed_mps = 3.0;

const char* const kApproachingWall =
    "objects:\n"
    "  - name: wall\n"
    "    box: {size_m: [0.2, 40, 40]}\n"
    "    pose: {position_m: [10.1, 0, 0]}\n"
    "    motion: {linear_velocity_mps: [-3, 0, 0]}\n";

TEST(AnalyticMotion, ApproachingWallAtEachBeamsInstant) {
  const scene::Scene scene = scene_from(kApproachingWall);
  for (const auto& options : kIndexOptions) {
    SceneCaster caster(scene, options);
    caster.prepare(0.5, 0.6);
    for (int beam = 0; beam <= 100; ++beam) {
      const double t = 0.5 + 0.001 * beam;
      const double theta = (beam - 50) * 0.004;  // spread the beams like a head would
      const auto hit = caster.cast(ray_at(Eigen::Vector3d::Zero(), Eigen::Vector3d(std::cos(theta), std::sin(theta), 0), t));
      ASSERT_TRUE(hit) << beam;
      const double expected = (kWallStart_m - kWallSpeed_mps * t) / std::cos(theta);
      EXPECT_NEAR(hit->range_m, expected, 1e-9) << "beam " << beam << " slices " << options.slices;
      EXPECT_EQ(hit->object_index, 0u);
    }
    // Outside the prepared window the answer is the same, found without the index.
    const auto late = caster.cast(ray_at(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 2.0));
    ASSERT_TRUE(late);
    EXPECT_NEAR(late->range_m, kWallStart_m - kWallSpeed_mps * 2.0, 1e-9);
  }
}

// A 2 m x 2 m box spinning about its own vertical axis, seen along +x through its axis: the near
// face is at 1 / cos(a) from the axis, a the angle to the nearest face normal.
TEST(AnalyticMotion, BoxSpinningAboutItsAxis) {
  const scene::Scene scene = scene_from(
      "objects:\n"
      "  - box: {size_m: [2, 2, 1]}\n"
      "    pose: {position_m: [6, 0, 0]}\n"
      "    motion: {angular_velocity_dps: [0, 0, 270]}\n");
  for (const auto& options : kIndexOptions) {
    SceneCaster caster(scene, options);
    caster.prepare(0.0, 1.0);
    for (int k = 0; k < 200; ++k) {
      const double t = k * 0.005 + 0.0001;
      const double turned = std::fmod(270.0 * t, 90.0);
      const double a = (turned > 45.0 ? turned - 90.0 : turned) * std::numbers::pi / 180.0;
      const auto hit = caster.cast(ray_at(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), t));
      ASSERT_TRUE(hit) << t;
      EXPECT_NEAR(hit->range_m, 6.0 - 1.0 / std::cos(a), 1e-9) << "t " << t;
      // The normal is the face's: turned by a from -x.
      EXPECT_NEAR(std::abs(hit->normal.x()), std::cos(a), 1e-9);
    }
  }
}

// The scanner's pivot drives towards a static wall: the sensor casts each beam from where the
// platform is at that beam's instant. The recorded ranges are the exact ones, before quantising.
TEST(AnalyticMotion, PlatformMovingTowardsAWall) {
  const scene::Scene scene = scene_from(
      "scanner:\n"
      "  pivot_pose: {position_m: [0, 0, 1]}\n"
      "  pivot_motion: {linear_velocity_mps: [0.8, 0.3, 0]}\n"
      "objects:\n"
      "  - box: {size_m: [0.2, 100, 100]}\n"
      "    pose: {position_m: [12.1, 0, 0]}\n");
  ASSERT_TRUE(scene.moves());
  SceneCaster caster(scene);
  testing::RecordingCaster recorder(caster);
  const sensor::SensorModel sensor(scene, recorder);
  std::vector<sensor::BeamRequest> beams;
  for (int k = 0; k < 50; ++k) beams.push_back({0.01 * k, 0.0, static_cast<std::uint32_t>(k), 0.2 * k});
  std::vector<sensor::BeamSample> samples(beams.size());
  caster.prepare(0.0, 10.0);
  sensor.measure(1, beams, samples);
  const auto ranges = recorder.ranges();
  ASSERT_EQ(ranges.size(), beams.size());
  for (std::size_t k = 0; k < beams.size(); ++k) {
    const double expected = (12.0 - 0.8 * beams[k].time_s) / std::cos(beams[k].head_angle_rad);
    EXPECT_NEAR(ranges[k], expected, 1e-9) << k;
  }
}

// Zero velocity: the moving caster answers what the static caster answers for the same solids.
TEST(AnalyticMotion, StandingStillMatchesTheStaticCaster) {
  const std::string solids =
      "  - box: {size_m: [1, 2, 3]}\n    pose: {position_m: [5, 1, 0], rpy_deg: [10, 20, 30]}\n"
      "  - sphere: {radius_m: 0.7}\n    pose: {position_m: [4, -2, 0.5]}\n"
      "  - cylinder: {radius_m: 0.4, length_m: 2}\n    pose: {position_m: [6, -0.5, -1], rpy_deg: [80, 0, 0]}\n"
      "  - capsule: {radius_m: 0.3, length_m: 1}\n    pose: {position_m: [3, 2.5, 0]}\n";
  std::string moving;
  for (std::size_t pos = 0; pos < solids.size();) {
    const std::size_t end = solids.find('\n', solids.find("pose:", pos));
    moving += solids.substr(pos, end - pos) + "\n    motion: {linear_velocity_mps: [0, 0, 0]}\n";
    pos = end + 1;
  }
  const scene::Scene still = scene_from("objects:\n" + solids);
  const scene::Scene standing = scene_from("objects:\n" + moving);
  ASSERT_FALSE(still.moves());
  ASSERT_TRUE(standing.moves());
  const raycast::OdeWorld world(still);
  const raycast::EmbreeRayCaster reference(world);
  SceneCaster caster(standing);
  caster.prepare(0.0, 1.0);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const double yaw = -1.2 + 2.4 * i / 2000.0;
    const double pitch = 0.5 * std::sin(i * 0.37);
    const Eigen::Vector3d direction(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), std::sin(pitch));
    const auto expected = reference.cast(ray_at(Eigen::Vector3d::Zero(), direction, 0.0));
    const auto got = caster.cast(ray_at(Eigen::Vector3d::Zero(), direction, 0.3));
    ASSERT_EQ(expected.has_value(), got.has_value()) << i;
    if (!expected) continue;
    ++hits;
    EXPECT_NEAR(got->range_m, expected->range_m, 1e-9) << i;
    EXPECT_EQ(got->object_index, expected->object_index) << i;
    EXPECT_NEAR((got->normal - expected->normal).norm(), 0.0, 1e-9) << i;
  }
  EXPECT_GT(hits, 200);
}

}  // namespace
}  // namespace ldoem::world
