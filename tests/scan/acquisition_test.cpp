// Whole scans through ScannerDevice against the scripted LD: the sequence of services, the
// tilt positions and every point of the cloud.
#include "ldoem/scan/acquisition.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <unistd.h>
#include <filesystem>

#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/protocol/service_codes.hpp"
#include "scanner_bench.hpp"

namespace ldoem::scan {
namespace {

using test::ScannerBench;

// Range in 1/256 m: 2 m plus a few mm per beam and per half-step of tilt.
std::uint16_t range_without_echo_on_beam_7(std::uint32_t beam, std::int64_t tilt_half_steps) {
  if (beam == 7) {
    return 0;  // no echo on one beam
  }
  return static_cast<std::uint16_t>(512 + beam + 2 * (tilt_half_steps + 1000));
}

AcquisitionPlan small_plan(bool half_step) {
  AcquisitionPlan plan;
  plan.sectors = plan_sectors(20.0, 0.25, 10).value();
  plan.layers = plan_layers(1.8, 0.18, half_step).value();  // 11 layers
  plan.step_rate_hz = 1000.0;
  return plan;
}

TEST(Acquire, ScriptedDevice_CloudMatchesTheScriptedRanges) {
  ScannerBench bench(range_without_echo_on_beam_7);
  const AcquisitionPlan plan = small_plan(false);
  std::vector<std::uint32_t> progress;
  AcquisitionHooks hooks;
  hooks.on_layer = [&progress](std::uint32_t done, std::uint32_t) { progress.push_back(done); };
  auto scan = acquire(*bench.device, plan, hooks);
  ASSERT_TRUE(scan) << describe(scan.error());

  const std::uint32_t layers = plan.layers.layer_count;
  ASSERT_EQ(layers, 11u);
  EXPECT_EQ(progress.size(), layers);
  EXPECT_EQ(scan->layers_done, layers);
  // Organised as seen from the scanner: row 0 = the highest layer, column 0 = the leftmost beam
  // (the largest head angle); beam 7 has no echo and is a NaN point.
  ASSERT_EQ(scan->cloud.size(), layers * 81u);
  ASSERT_EQ(scan->cloud.organised(), (cloud::OrganisedSize{81u, layers}));
  for (std::uint32_t layer = 0; layer < layers; ++layer) {
    const std::int64_t half_steps = -20 + 4 * static_cast<std::int64_t>(layer);  // -0.9 deg .. +0.9 deg
    const double phi = half_steps * 0.045 * M_PI / 180.0;
    for (std::uint32_t beam = 0; beam < 81; ++beam) {
      const std::uint32_t row = layers - 1 - layer;
      const std::uint32_t column = 80 - beam;
      const cloud::PointRecord point = scan->cloud.record(std::size_t{row} * 81 + column);
      const double theta = (-10.0 + 0.25 * beam) * M_PI / 180.0;
      EXPECT_EQ(point.ring, layer);
      EXPECT_EQ(point.image_position, (cloud::ImagePosition{row, column}));
      EXPECT_NEAR(point.azimuth_rad, theta, 1e-6);
      EXPECT_NEAR(point.tilt_rad, phi, 1e-6);
      if (beam == 7) {
        EXPECT_TRUE(std::isnan(point.position.x_m) && std::isnan(point.range_m)) << layer;
        continue;
      }
      const double range_m = range_without_echo_on_beam_7(beam, half_steps) / 256.0;
      EXPECT_NEAR(point.range_m, range_m, 1e-6);
      EXPECT_NEAR(point.position.x_m, range_m * std::cos(theta) * std::cos(phi), 1e-5) << layer << "/" << beam;
      EXPECT_NEAR(point.position.y_m, range_m * std::sin(theta), 1e-5) << layer << "/" << beam;
      EXPECT_NEAR(point.position.z_m, range_m * std::cos(theta) * std::sin(phi), 1e-5) << layer << "/" << beam;
      EXPECT_FLOAT_EQ(point.intensity, 100.0F + beam);
    }
  }
  // t: the scripted LD sends TSTART = TEND = 0, so every beam is at 0 (scan_grid_test.cpp
  // checks the timing).
  EXPECT_EQ(scan->cloud.record(0).time_s, 0.0F);
  // The scan ends in IDLE with the plate home.
  EXPECT_EQ(bench.ld.mode(), protocol::SensorMode::idle);
  EXPECT_EQ(bench.port->position_half_steps(), 0);
  EXPECT_EQ(bench.ld.global().angle_step_ticks, 4);
  EXPECT_EQ(bench.ld.profiles_sent(), layers);
}

TEST(Acquire, Sequence_FollowsThePaper) {
  ScannerBench bench(range_without_echo_on_beam_7);
  auto scan = acquire(*bench.device, small_plan(true));
  ASSERT_TRUE(scan) << describe(scan.error());
  const auto& seen = bench.ld.requests;
  const auto code = [](protocol::Service s) { return static_cast<std::uint16_t>(s); };
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.front(), code(protocol::Service::get_status));
  const auto first = [&](protocol::Service s) {
    return std::find(seen.begin(), seen.end(), code(s)) - seen.begin();
  };
  EXPECT_LT(first(protocol::Service::get_identification), first(protocol::Service::set_function));
  EXPECT_LT(first(protocol::Service::set_function), first(protocol::Service::trans_rotate));
  EXPECT_LT(first(protocol::Service::trans_rotate), first(protocol::Service::trans_measure));
  EXPECT_LT(first(protocol::Service::trans_measure), first(protocol::Service::get_profile));
  EXPECT_EQ(std::count(seen.begin(), seen.end(), code(protocol::Service::get_profile)), 11);
  EXPECT_EQ(seen.back(), code(protocol::Service::trans_idle));
  EXPECT_EQ(bench.port->position_half_steps(), 0);
}

TEST(Acquire, DeviceRefusesMidScan_ReportsTheLayerAndCleansUp) {
  ScannerBench bench(range_without_echo_on_beam_7);
  bench.ld.refuse_profiles_after = 3;
  auto scan = acquire(*bench.device, small_plan(false));
  ASSERT_FALSE(scan);
  EXPECT_EQ(scan.error().failure, AcquisitionFailure::device_error);
  EXPECT_EQ(scan.error().stage, "GET2DPROFILE layer 3");
  ASSERT_TRUE(scan.error().error);
  EXPECT_EQ(scan.error().error->kind, driver::ErrorKind::service_failure);
  EXPECT_FALSE(scan.error().cleanup_error);
  EXPECT_EQ(bench.ld.mode(), protocol::SensorMode::idle);
  EXPECT_EQ(bench.port->position_half_steps(), 0);
}

TEST(Acquire, StopRequest_EndsWithCleanUp) {
  ScannerBench bench(range_without_echo_on_beam_7);
  int polls = 0;
  AcquisitionHooks hooks;
  hooks.should_stop = [&polls] { return ++polls > 4; };
  auto scan = acquire(*bench.device, small_plan(false), hooks);
  ASSERT_FALSE(scan);
  EXPECT_EQ(scan.error().failure, AcquisitionFailure::stopped);
  EXPECT_EQ(bench.ld.mode(), protocol::SensorMode::idle);
  EXPECT_EQ(bench.port->position_half_steps(), 0);
}

TEST(Acquire, CloudFile_RoundTripsThroughPly) {
  ScannerBench bench(range_without_echo_on_beam_7);
  auto scan = acquire(*bench.device, small_plan(false));
  ASSERT_TRUE(scan) << describe(scan.error());
  const auto path = std::filesystem::temp_directory_path() / ("ldoem_scan_test_" + std::to_string(::getpid()) + ".ply");
  ASSERT_TRUE(cloud::write_cloud_file(path, scan->cloud, cloud::CloudFileFormat::ply_binary));
  auto back = cloud::read_cloud_file(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(back);
  ASSERT_EQ(back->size(), scan->cloud.size());
  for (std::size_t i = 0; i < back->size(); i += 97) {
    EXPECT_EQ(back->positions()[i], scan->cloud.positions()[i]);
  }
}

}  // namespace
}  // namespace ldoem::scan
