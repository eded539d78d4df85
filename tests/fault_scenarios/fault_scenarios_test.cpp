// scenes/faults/ against ldoem-emud over TCP: what each scene's header says a robust driver does,
// done by libldoem or ldoem-scan and asserted (docs/faults.md, "Host side"). Real time, so each
// fault comes at the device time its scene names.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "ldoem/base/device_constants.hpp"
#include "scenario_device.hpp"

namespace ldoem::fault_scenarios {
namespace {

namespace p = protocol;
using driver::DriverError;
using driver::ErrorKind;
using driver::Recovery;
using namespace std::chrono_literals;

struct ExpectedBeam {
  double angle_deg;
  std::uint16_t distance;
  std::uint16_t echo;
};

// Every point of a profile with its head angle (STARTDIR + k DIRSTEP, spec 3.5).
std::vector<ExpectedBeam> beams_of(const p::Profile& profile) {
  std::vector<ExpectedBeam> beams;
  for (const auto& sector : profile.sectors) {
    for (std::size_t k = 0; k < sector.points.size(); ++k) {
      const auto ticks = (sector.start_dir_ticks + k * sector.dir_step_ticks) % base::kTicksPerTurn;
      beams.push_back({static_cast<double>(ticks) / 16.0, sector.points[k].distance_q8_m, sector.points[k].echo});
    }
  }
  return beams;
}

// Measures 320..40 deg (in front) and 160..200 deg (behind), rotates, measures, and returns one
// fresh profile. (A whole turn at 0.25 deg and 10 Hz is above the mean pulse frequency, spec 3.3.)
std::optional<p::Profile> front_and_back_profile(driver::Scanner& scanner, std::string& failure) {
  using namespace p::sector_function;
  const std::vector<driver::SectorDefinition> table{
      {kNormalMeasurement, 40 * 16}, {kNoMeasurement, 160 * 16}, {kNormalMeasurement, 200 * 16}, {kNoMeasurement, 320 * 16}};
  if (auto written = scanner.write_sector_table(table, false); !written) {
    failure = describe(written.error());
    return std::nullopt;
  }
  for (auto step : {0, 1}) {
    auto done = step == 0 ? scanner.trans_rotate() : scanner.trans_measure();
    if (!done) {
      failure = describe(done.error());
      return std::nullopt;
    }
  }
  if (auto asked = scanner.get_profile(1, p::kFormatRangeEcho); !asked) {
    failure = describe(asked.error());
    return std::nullopt;
  }
  auto profile = scanner.next_profile(driver::Clock::now() + 5s);
  if (!profile) {
    failure = describe(profile.error());
    return std::nullopt;
  }
  return std::move(*profile);
}

// ------------------------------------------------------------------- motor-stall-mid-stream

TEST(FaultScenario, MotorStallMidStream_TimeoutThenFinalFault_ResetAndSpinAgain) {
  std::string failure;
  auto scene = start_scene(scenario("motor-stall-mid-stream"), {}, &failure);
  ASSERT_TRUE(scene) << failure;
  auto scanner = connect_scanner(*scene);
  ASSERT_TRUE(scanner);
  ASSERT_TRUE(scanner->trans_rotate());
  ASSERT_TRUE(scanner->trans_measure());
  ASSERT_LT(scene->elapsed_s(), 3.8) << "the head took too long to spin up: the stall would come first";
  ASSERT_TRUE(scanner->get_profile(0, p::kFormatRange));
  // The stream runs, then stops at 4 s: the driver notices a timeout (retryable), never hangs.
  int profiles = 0;
  DriverError stopped;
  for (;;) {
    auto profile = scanner->next_profile(driver::Clock::now() + 1s);
    if (!profile) {
      stopped = profile.error();
      break;
    }
    ++profiles;
    ASSERT_LT(scene->elapsed_s(), 10.0) << "the stream did not stop";
  }
  EXPECT_GT(profiles, 0);
  EXPECT_EQ(stopped.kind, ErrorKind::timeout) << describe(stopped);
  EXPECT_TRUE(driver::is_retryable(stopped));
  // GET_STATUS names the fault: final until reset.
  auto status = scanner->get_status();
  ASSERT_TRUE(status) << describe(status.error());
  auto fault = driver::device_fault_in(status->status, "GET_STATUS", "emud");
  ASSERT_TRUE(fault) << "status " << int(status->status.status.to_byte());
  EXPECT_EQ(driver::recovery_for(*fault), Recovery::reset_device);
  EXPECT_NE(status->status.status.motor, p::MotorMode::ok);
  // ERROR comes one revolution after the nibble: then TRANS_IDLE is refused (reason 3, final).
  for (int i = 0; i < 30 && scanner->get_status()->status.status.sensor != p::SensorMode::error; ++i) {
    std::this_thread::sleep_for(100ms);
  }
  const auto in_error = scanner->get_status()->status.status;
  ASSERT_EQ(in_error.sensor, p::SensorMode::error);  // 0x44 while the head coasts, 0xB4 stopped
  EXPECT_NE(in_error.motor, p::MotorMode::ok);
  auto idle = scanner->trans_idle();
  ASSERT_FALSE(idle);
  EXPECT_EQ(idle.error().kind, ErrorKind::service_failure);
  EXPECT_EQ(idle.error().failure_reason, p::FailureReason::wrong_state);
  EXPECT_FALSE(driver::is_retryable(idle.error()));
  // DO_RESET level 2; once the stall is over (6 s) TRANS_ROTATE spins the head up again.
  scene->wait_until_s(6.2);
  ASSERT_TRUE(scanner->do_reset(p::reset_level::kHaltToIdle));
  auto rotating = scanner->trans_rotate();
  ASSERT_TRUE(rotating) << describe(rotating.error());
  EXPECT_EQ(rotating->status.to_byte(), 0x02);
}

TEST(FaultScenario, MotorStallMidStream_LdoemScanExitsOneNamingTheFault_NoCloudLeft) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("ldoem-stall-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string lpt = (dir / "lpt").string();
  const std::string out = (dir / "scan.ply").string();
  std::string failure;
  auto scene = start_scene(scenario("motor-stall-mid-stream"), {"--lpt", "lpt:pty:" + lpt}, &failure);
  ASSERT_TRUE(scene) << failure;
  auto scan = daemon::test::DaemonProcess::start_program(
      LDOEM_SCAN_PATH, {"--device", "tcp:127.0.0.1:" + std::to_string(scene->endpoint.port), "--lpt", "lpt:pty:" + lpt,
                        "--vertical-apex", "9", "--retries", "3", "--timeout", "1", "--out", out});
  ASSERT_TRUE(scan);
  const auto status = scan->wait(120s);
  const std::string text = scan->stderr_text();
  ASSERT_EQ(status, std::optional<int>(1)) << text;
  EXPECT_NE(text.find("device fault: status 0x"), std::string::npos) << text;
  EXPECT_NE(text.find("motor"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(out)) << "a partial cloud under the output name";
  std::size_t left = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++left;
  EXPECT_EQ(left, 1u) << "only the LPT link may remain, no temporary cloud";
  std::filesystem::remove_all(dir);
}

// ---------------------------------------------------------------- power-cycle / reset mid-scan

// ldoem-scan with --retries over a scene whose fault comes mid-scan: it completes, every layer.
void scan_completes_through(const std::string& name, const std::string& expected_retry_words) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("ldoem-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string lpt = (dir / "lpt").string();
  const std::string out = (dir / "scan.ply").string();
  std::string failure;
  auto scene = start_scene(scenario(name), {"--lpt", "lpt:pty:" + lpt}, &failure);
  ASSERT_TRUE(scene) << failure;
  // 9 deg at 0.18 deg: 51 layers, about 15 s: the fault (5 s, 6 s) comes in the middle.
  auto scan = daemon::test::DaemonProcess::start_program(
      LDOEM_SCAN_PATH, {"--device", "tcp:127.0.0.1:" + std::to_string(scene->endpoint.port), "--lpt", "lpt:pty:" + lpt,
                        "--vertical-apex", "9", "--retries", "3", "--timeout", "2", "--out", out});
  ASSERT_TRUE(scan);
  const auto status = scan->wait(150s);
  const std::string text = scan->stderr_text();
  ASSERT_EQ(status, std::optional<int>(0)) << text;
  EXPECT_NE(text.find("in 51 layers written"), std::string::npos) << text;
  EXPECT_NE(text.find(expected_retry_words), std::string::npos) << text;
  EXPECT_NE(text.find("restarts after faults"), std::string::npos) << text;
  EXPECT_TRUE(std::filesystem::exists(out));
  std::filesystem::remove_all(dir);
}

TEST(FaultScenario, PowerCycleDuringProfile_LdoemScanReconnectsAndCompletes) {
  scan_completes_through("power-cycle-during-profile", "retryable after a reconnect");
}

TEST(FaultScenario, SpontaneousReset_LdoemScanMeasuresAgainAndCompletes) {
  scan_completes_through("spontaneous-reset", "; retry 1 of 3");
}

TEST(FaultScenario, PowerCycleDuringProfile_ScannerReconnectsToThePowerUpState) {
  std::string failure;
  auto scene = start_scene(scenario("power-cycle-during-profile"), {}, &failure);
  ASSERT_TRUE(scene) << failure;
  auto scanner = connect_scanner(*scene);
  ASSERT_TRUE(scanner);
  ASSERT_TRUE(scanner->trans_rotate());
  ASSERT_TRUE(scanner->trans_measure());
  ASSERT_TRUE(scanner->get_profile(0, p::kFormatRange));
  DriverError lost;
  while (true) {
    auto profile = scanner->next_profile(driver::Clock::now() + 2s);
    if (!profile) {
      lost = profile.error();
      break;
    }
    ASSERT_LT(scene->elapsed_s(), 8.0);
  }
  EXPECT_EQ(lost.kind, ErrorKind::connection_closed) << describe(lost);
  EXPECT_EQ(driver::recovery_for(lost), Recovery::reconnect);
  auto status = scanner->reconnect();  // off for 1.5 s: a few attempts, 500 ms apart
  ASSERT_TRUE(status) << describe(status.error());
  EXPECT_EQ(status->status.status.to_byte(), 0x01);  // D4 power-up: IDLE, motor stopped
  // Only after the power came back (5 s + 1.5 s of device time; the host's clock started a
  // little later than the device's, hence the margin).
  EXPECT_GE(scene->elapsed_s(), 6.0);
  EXPECT_EQ(scanner->counters().reconnects, 1u);
}

// -------------------------------------------------------------------------------- flaky-tcp

TEST(FaultScenario, FlakyTcp_RetriesTimeoutsReconnectsAfterTheReset_EveryAnswerRight) {
  std::string failure;
  auto scene = start_scene(scenario("flaky-tcp"), {}, &failure);
  ASSERT_TRUE(scene) << failure;
  driver::ScannerOptions options;
  options.request_timeout = 400ms;  // a 300 ms delay still arrives in time
  auto scanner = connect_scanner(*scene, options);
  ASSERT_TRUE(scanner);
  int answered = 0;
  int timeouts = 0;
  int reconnects = 0;
  while (scene->elapsed_s() < 10.0) {
    auto status = scanner->get_status();
    if (status) {
      ++answered;
      EXPECT_EQ(status->status.status.to_byte(), 0x01);
      continue;
    }
    const DriverError& error = status.error();
    ASSERT_TRUE(driver::is_retryable(error)) << describe(error);
    if (driver::recovery_for(error) == Recovery::reconnect) {
      ++reconnects;
      ASSERT_TRUE(scanner->reconnect());
    } else {
      EXPECT_EQ(error.kind, ErrorKind::timeout) << describe(error);
      ++timeouts;
    }
  }
  EXPECT_GT(answered, 50);
  EXPECT_GE(timeouts, answered / 7 - 2) << "every 7th reply is dropped";
  EXPECT_EQ(reconnects, 1) << "one reset at 8 s";
}

// --------------------------------------------------------------------------- encoder-error

TEST(FaultScenario, EncoderError_FinalFault_RotateFailsAtOnceAfterReset) {
  std::string failure;
  auto scene = start_scene(scenario("encoder-error"), {}, &failure);
  ASSERT_TRUE(scene) << failure;
  auto scanner = connect_scanner(*scene);
  ASSERT_TRUE(scanner);
  ASSERT_TRUE(scanner->trans_rotate());
  for (int n = 1; n <= 2; ++n) {
    ASSERT_TRUE(scanner->trans_measure()) << n;
    ASSERT_TRUE(scanner->trans_rotate()) << n;  // back to ROTATE for the next TRANS_MEASURE
  }
  auto third = scanner->trans_measure();  // the encoder fails on this one
  ASSERT_FALSE(third);
  EXPECT_FALSE(driver::is_retryable(third.error())) << describe(third.error());
  auto status = scanner->get_status();
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status.status.to_byte(), 0xB4);
  ASSERT_TRUE(scanner->do_reset(p::reset_level::kHaltToIdle));
  // The fault lasts: TRANS_ROTATE fails at once with 0xB4, a final device fault; no loop.
  const auto asked = Clock::now();
  auto rotating = scanner->trans_rotate();
  ASSERT_FALSE(rotating);
  EXPECT_LT(Clock::now() - asked, 2s);
  EXPECT_EQ(rotating.error().kind, ErrorKind::device_fault);
  EXPECT_EQ(rotating.error().device_status, 0xB4);
  EXPECT_EQ(driver::recovery_for(rotating.error()), Recovery::reset_device);
}

// --------------------------------------------------------------------------- blinded-sector

TEST(FaultScenario, BlindedSector_DistanceZeroThere_OtherBeamsUnchanged) {
  std::string failure;
  auto scene = start_scene(scenario("blinded-sector"), {}, &failure);
  ASSERT_TRUE(scene) << failure;
  auto scanner = connect_scanner(*scene);
  ASSERT_TRUE(scanner);
  scene->wait_until_s(3.5);  // blind from 3 s to 13 s
  auto profile = front_and_back_profile(*scanner, failure);
  ASSERT_TRUE(profile) << failure;
  int blinded = 0;
  int seen_wall = 0;
  for (const ExpectedBeam& beam : beams_of(*profile)) {
    const bool in_sector = beam.angle_deg >= 350.0 || beam.angle_deg < 10.0;
    if (in_sector) {
      ++blinded;
      EXPECT_EQ(beam.distance, 0) << beam.angle_deg;  // no echo (D3), never a range of 0 m
      EXPECT_EQ(beam.echo, 0) << beam.angle_deg;
    } else if (beam.angle_deg >= 15.0 && beam.angle_deg <= 50.0) {
      ++seen_wall;
      const double expected_m = 5.0 / std::cos(beam.angle_deg * M_PI / 180.0);
      EXPECT_NEAR(beam.distance / 256.0, expected_m, 0.1) << beam.angle_deg;
    }
  }
  EXPECT_GT(blinded, 30);
  EXPECT_GT(seen_wall, 60);
}

// ----------------------------------------------------------------------------- dirty-window

// Valid returns (DISTANCE > 0) of the far dark wall (behind, 160..200 deg) and of the near
// wall (in front, -40..40 deg) in one profile of `scene_path`.
std::pair<int, int> valid_returns(const std::string& scene_path, std::string& failure) {
  auto scene = start_scene(scene_path, {}, &failure);
  if (!scene) return {-1, -1};
  auto scanner = connect_scanner(*scene);
  if (!scanner) return {-1, -1};
  auto profile = front_and_back_profile(*scanner, failure);
  if (!profile) return {-1, -1};
  int far = 0;
  int near = 0;
  for (const ExpectedBeam& beam : beams_of(*profile)) {
    if (beam.distance == 0) continue;
    if (beam.angle_deg >= 160.0 && beam.angle_deg <= 200.0) ++far;
    if (beam.angle_deg <= 40.0 || beam.angle_deg >= 320.0) ++near;
  }
  return {far, near};
}

TEST(FaultScenario, DirtyWindow_FarDarkTargetsDropOut_NearOnesStay_NoError) {
  std::string failure;
  const auto [far_dirty, near_dirty] = valid_returns(scenario("dirty-window"), failure);
  ASSERT_GE(far_dirty, 0) << failure;
  // The same scene with a clean window, for contrast.
  std::ifstream in(scenario("dirty-window"));
  std::stringstream text;
  for (std::string line; std::getline(in, line);) {
    if (line.find("window_dirt") == std::string::npos && line != "faults:") text << line << "\n";
  }
  const auto clean_path = std::filesystem::temp_directory_path() / ("ldoem-clean-window-" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(clean_path) << text.str();
  const auto [far_clean, near_clean] = valid_returns(clean_path.string(), failure);
  std::filesystem::remove(clean_path);
  ASSERT_GE(far_clean, 0) << failure;
  EXPECT_GT(far_clean, 20) << "the far dark wall answers through a clean window";
  EXPECT_LT(far_dirty, far_clean / 4) << "most of it drops out behind the dirt";
  EXPECT_GT(near_dirty, 100);
  EXPECT_EQ(near_dirty, near_clean) << "the near bright wall still answers everywhere";
}

}  // namespace
}  // namespace ldoem::fault_scenarios
