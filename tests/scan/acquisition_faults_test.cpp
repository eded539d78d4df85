// Scans through ScannerDevice against the scripted LD with D11 faults at a chosen GET_PROFILE:
// retryable faults are retried and the scan completes with the same cloud; a lost connection or
// a spontaneous reset is measured again first; a motor fault is final and named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>

#include "ldoem/scan/acquisition.hpp"
#include "scanner_bench.hpp"

namespace ldoem::scan {
namespace {

using test::ScannerBench;
using test::ScriptedLd;
using Fault = ScriptedLd::Fault;

std::uint16_t scripted_range(std::uint32_t beam, std::int64_t tilt_half_steps) {
  return static_cast<std::uint16_t>(512 + beam + 2 * (tilt_half_steps + 1000));
}

AcquisitionPlan small_plan(std::uint32_t retries = 3) {
  AcquisitionPlan plan;
  plan.sectors = plan_sectors(20.0, 0.25, 10).value();
  plan.layers = plan_layers(1.8, 0.18, false).value();  // 11 layers
  plan.step_rate_hz = 1000.0;
  plan.retries = retries;
  return plan;
}

struct Retry {
  std::string stage;
  driver::ErrorKind kind;
};

struct AcquisitionRun {
  base::Expected<Scan, AcquisitionError> scan;
  std::vector<Retry> retries;
};

AcquisitionRun scan_with(ScannerBench& bench, const AcquisitionPlan& plan) {
  std::vector<Retry> retries;
  AcquisitionHooks hooks;
  hooks.sleep = [](std::chrono::milliseconds) {};
  hooks.on_retry = [&retries](const std::string& stage, const driver::DriverError& error, std::uint32_t, std::uint32_t) {
    retries.push_back({stage, error.kind});
  };
  auto scan = acquire(*bench.device, plan, hooks);
  return {std::move(scan), std::move(retries)};
}

// Same points, channels and order.
bool same_cloud(const cloud::PointCloud& a, const cloud::PointCloud& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!(a.record(i) == b.record(i))) return false;
  }
  return true;
}

cloud::PointCloud healthy_cloud() {
  ScannerBench bench(scripted_range);
  auto run = scan_with(bench, small_plan());
  EXPECT_TRUE(run.scan);
  return run.scan ? run.scan->cloud : cloud::PointCloud{};
}

TEST(AcquireFaults, DroppedOrTruncatedProfile_IsRetried_SameCloud) {
  const cloud::PointCloud expected = healthy_cloud();
  for (const auto& [fault, kind] : {std::pair{Fault::drop_reply, driver::ErrorKind::timeout},
                                    std::pair{Fault::truncate_reply, driver::ErrorKind::corrupted_reply}}) {
    ScannerBench bench(scripted_range);
    bench.ld.faults_at_profile_request[4] = fault;
    auto run = scan_with(bench, small_plan());
    ASSERT_TRUE(run.scan) << describe(run.scan.error());
    ASSERT_EQ(run.retries.size(), 1u);
    EXPECT_EQ(run.retries[0].stage, "GET2DPROFILE layer 3");
    EXPECT_EQ(run.retries[0].kind, kind);
    EXPECT_EQ(run.scan->retries_used, 1u);
    EXPECT_EQ(run.scan->restarts, 0u);
    EXPECT_EQ(run.scan->layers_done, 11u);
    EXPECT_EQ(run.scan->cloud.size(), expected.size());
    EXPECT_TRUE(same_cloud(run.scan->cloud, expected));
    EXPECT_EQ(bench.count(protocol::Service::get_profile), 12u);
  }
}

TEST(AcquireFaults, ConnectionLost_ReconnectsConfiguresAgain_AndCompletes) {
  const cloud::PointCloud expected = healthy_cloud();
  ScannerBench bench(scripted_range);
  bench.ld.faults_at_profile_request[6] = Fault::connection_lost;  // a power cycle mid-scan
  auto run = scan_with(bench, small_plan());
  ASSERT_TRUE(run.scan) << describe(run.scan.error());
  ASSERT_EQ(run.retries.size(), 1u);
  EXPECT_EQ(run.retries[0].kind, driver::ErrorKind::connection_closed);
  EXPECT_EQ(run.scan->restarts, 1u);
  EXPECT_EQ(bench.transports_opened, 2);
  EXPECT_EQ(bench.count(protocol::Service::trans_rotate), 2u + 1u);  // start, restart, and the way to IDLE
  EXPECT_EQ(bench.ld.global().angle_step_ticks, small_plan().sectors.angle_step_ticks);  // configured again
  EXPECT_TRUE(same_cloud(run.scan->cloud, expected));
  EXPECT_EQ(bench.port->position_half_steps(), 0);
}

TEST(AcquireFaults, SpontaneousReset_MeasuresAgain_AndCompletes) {
  const cloud::PointCloud expected = healthy_cloud();
  ScannerBench bench(scripted_range);
  bench.ld.faults_at_profile_request[8] = Fault::reset_spontaneous;
  auto run = scan_with(bench, small_plan());
  ASSERT_TRUE(run.scan) << describe(run.scan.error());
  EXPECT_EQ(run.scan->restarts, 1u);
  EXPECT_EQ(bench.count(protocol::Service::trans_measure), 2u);
  EXPECT_TRUE(same_cloud(run.scan->cloud, expected));
}

TEST(AcquireFaults, MotorStall_IsFinal_NamedWithItsStatus_NoRetry) {
  ScannerBench bench(scripted_range);
  bench.ld.faults_at_profile_request[5] = Fault::motor_stall;
  auto run = scan_with(bench, small_plan());
  ASSERT_FALSE(run.scan);
  EXPECT_TRUE(run.retries.empty());
  EXPECT_EQ(run.scan.error().stage, "GET2DPROFILE layer 4");
  ASSERT_TRUE(run.scan.error().error);
  EXPECT_EQ(run.scan.error().error->kind, driver::ErrorKind::device_fault);
  EXPECT_EQ(run.scan.error().error->device_status, 0xB4);
  const std::string message = describe(run.scan.error());
  EXPECT_NE(message.find("device fault: status 0xB4 (motor nibble 0x0B: motor fault, sensor mode ERROR)"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("after GET_PROFILE"), std::string::npos) << message;  // what showed it: the timeout
  // The clean-up leaves ERROR alone (TRANS_IDLE would be refused) and brings the tilt home.
  EXPECT_FALSE(run.scan.error().cleanup_error);
  EXPECT_EQ(bench.count(protocol::Service::trans_idle), 0u);
  EXPECT_EQ(bench.port->position_half_steps(), 0);
}

TEST(AcquireFaults, RetriesZero_FirstRetryableFaultEndsTheScan) {
  ScannerBench bench(scripted_range);
  bench.ld.faults_at_profile_request[2] = Fault::drop_reply;
  auto run = scan_with(bench, small_plan(0));
  ASSERT_FALSE(run.scan);
  EXPECT_EQ(run.scan.error().error->kind, driver::ErrorKind::timeout);
  EXPECT_EQ(run.scan.error().stage, "GET2DPROFILE layer 1");
}

TEST(AcquireFaults, RetriesUsedUp_EndsWithTheLastFault) {
  ScannerBench bench(scripted_range);
  for (std::size_t n = 3; n <= 6; ++n) {
    bench.ld.faults_at_profile_request[n] = Fault::drop_reply;
  }
  auto run = scan_with(bench, small_plan(3));
  ASSERT_FALSE(run.scan);
  EXPECT_EQ(run.retries.size(), 3u);
  EXPECT_EQ(run.scan.error().error->kind, driver::ErrorKind::timeout);
  EXPECT_EQ(run.scan.error().stage, "GET2DPROFILE layer 2");
  EXPECT_EQ(bench.count(protocol::Service::get_profile), 6u);
}

}  // namespace
}  // namespace ldoem::scan

namespace ldoem::scan {
namespace {

TEST(AcquireFaults, UnreachableDevice_IsFinalAtInitialize_NoRetry) {
  driver::TransportFactory refused = []() -> driver::Expected<std::unique_ptr<driver::TelegramTransport>, driver::DriverError> {
    return driver::fail(driver::system_error("connect", "tcp:127.0.0.1:1", ECONNREFUSED));
  };
  driver::ScannerDevice device("nowhere", refused, {}, std::make_unique<test::VirtualSleeper>());
  std::uint32_t retries = 0;
  AcquisitionHooks hooks;
  hooks.sleep = [](std::chrono::milliseconds) {};
  hooks.on_retry = [&retries](const std::string&, const driver::DriverError&, std::uint32_t, std::uint32_t) { ++retries; };
  auto plan = small_plan();
  plan.layers = plan_layers(0.0, 0.18, false).value();
  auto scan = acquire(device, plan, hooks);
  ASSERT_FALSE(scan);
  EXPECT_EQ(scan.error().stage, "INITIALIZE");
  EXPECT_EQ(scan.error().error->kind, driver::ErrorKind::system);
  EXPECT_EQ(retries, 0u);
}

}  // namespace
}  // namespace ldoem::scan
