#include "ldoem/scan/scan_options.hpp"

#include <gtest/gtest.h>

namespace ldoem::scan {
namespace {

std::vector<std::string_view> words(std::initializer_list<std::string_view> list) { return list; }

TEST(ScanOptions, DirectMinimal_TakesThePaperDefaults) {
  auto options = parse_scan_options(words({"--device", "can:vcan0", "--lpt", "lpt:pty:/tmp/l", "--out", "a.ply"}));
  ASSERT_TRUE(options) << options.error();
  EXPECT_EQ(options->horizontal_apex_deg, 20.0);
  EXPECT_EQ(options->horizontal_resolution_deg, 0.25);
  EXPECT_EQ(options->vertical_apex_deg, 21.6);
  EXPECT_EQ(options->vertical_resolution_deg, 0.18);
  EXPECT_EQ(options->speed_hz, 10);
  EXPECT_FALSE(options->half_step);
  EXPECT_EQ(options->encoding, CloudEncoding::binary);
  EXPECT_EQ(options->timeout, std::chrono::milliseconds(5000));
  ASSERT_TRUE(options->device);
  EXPECT_TRUE(std::holds_alternative<driver::CanEndpoint>(*options->device));
}

TEST(ScanOptions, Reconnect_DefaultsAreLibldoemsAndEachOptionIsRead) {
  auto defaults = parse_scan_options(words({"--device", "tcp:127.0.0.1:49152", "--out", "a.ply", "--vertical-apex", "0"}));
  ASSERT_TRUE(defaults) << defaults.error();
  EXPECT_EQ(defaults->reconnect, driver::ReconnectPolicy{});
  auto options = parse_scan_options(words({"--device", "tcp:127.0.0.1:49152", "--out", "a.ply", "--reconnect-attempts",
                                           "40", "--reconnect-interval", "0.25", "--reconnect-backoff", "2"}));
  ASSERT_TRUE(options) << options.error();
  EXPECT_EQ(options->reconnect.attempts, 40u);
  EXPECT_EQ(options->reconnect.interval, std::chrono::milliseconds(250));
  EXPECT_EQ(options->reconnect.backoff, 2.0);
  EXPECT_EQ(options->reconnect.max_interval, std::chrono::milliseconds(30000));
  // A first pause above the 30 s cap raises the cap: evenly spaced pauses of that length.
  auto long_pause = parse_scan_options(words({"--device", "tcp:127.0.0.1:49152", "--out", "a.ply", "--reconnect-interval", "45"}));
  ASSERT_TRUE(long_pause) << long_pause.error();
  EXPECT_EQ(driver::reconnect_pause(long_pause->reconnect, 5), std::chrono::milliseconds(45000));
  for (const auto& [option, value] : {std::pair{"--reconnect-attempts", "0"}, {"--reconnect-attempts", "1001"},
                                      {"--reconnect-interval", "0"}, {"--reconnect-interval", "61"},
                                      {"--reconnect-backoff", "0.5"}, {"--reconnect-backoff", "11"},
                                      {"--reconnect-backoff", "nan"}}) {
    const auto refused = parse_scan_options(words({"--device", "tcp:127.0.0.1:49152", "--out", "a.ply", option, value}));
    EXPECT_FALSE(refused) << option << " " << value;
  }
  const auto through_hub = parse_scan_options(
      words({"--hub", "127.0.0.1:49201", "--hub-device", "left", "--out", "a.ply", "--reconnect-attempts", "3"}));
  ASSERT_FALSE(through_hub);
  EXPECT_NE(through_hub.error().find("a hub reconnects"), std::string::npos) << through_hub.error();
}

TEST(ScanOptions, EveryOption_IsRead) {
  auto options = parse_scan_options(
      words({"--hub", "127.0.0.1:49201", "--hub-device", "left", "--horizontal-apex", "40", "--horizontal-resolution",
             "0.5", "--vertical-apex", "9", "--vertical-resolution", "0.09", "--speed", "5", "--half-step",
             "--step-rate", "400", "--out", "x.PCD", "--format", "ascii", "--preview", "p.png", "--render", "r.png", "--render-colour", "intensity", "--fit", "--timeout",
             "2.5", "--optical-offset", "0.1,-0.02,0.3"}));
  ASSERT_TRUE(options) << options.error();
  ASSERT_TRUE(options->hub);
  EXPECT_EQ(options->hub->port, 49201);
  EXPECT_EQ(options->hub_device, "left");
  EXPECT_EQ(options->horizontal_apex_deg, 40.0);
  EXPECT_EQ(options->speed_hz, 5);
  EXPECT_TRUE(options->half_step);
  EXPECT_EQ(options->step_rate_hz, 400.0);
  EXPECT_TRUE(options->fit);
  EXPECT_EQ(options->preview_path, "p.png");
  EXPECT_EQ(options->render_path, "r.png");
  EXPECT_EQ(options->render_colour, cloud::RenderColour::intensity);
  EXPECT_EQ(options->timeout, std::chrono::milliseconds(2500));
  EXPECT_EQ(options->optical_offset_m, (Vector3{0.1, -0.02, 0.3}));
  EXPECT_EQ(output_format(options->out_path, options->encoding), cloud::CloudFileFormat::pcd_ascii);
}

TEST(ScanOptions, BadCombinations_AreUsageErrors) {
  EXPECT_FALSE(parse_scan_options(words({"--out", "a.ply"})));  // no device
  EXPECT_FALSE(parse_scan_options(words({"--device", "tcp:h", "--hub", "h:1", "--hub-device", "d", "--out", "a.ply"})));
  EXPECT_FALSE(parse_scan_options(words({"--hub", "h:1", "--out", "a.ply"})));
  EXPECT_FALSE(parse_scan_options(words({"--hub", "h:1", "--hub-device", "d", "--lpt", "lpt:pty:/x", "--out", "a.ply"})));
  EXPECT_FALSE(parse_scan_options(words({"--device", "tcp:h"})));                    // no --out
  EXPECT_FALSE(parse_scan_options(words({"--device", "tcp:h", "--out", "a.xyz"})));  // extension
  EXPECT_FALSE(parse_scan_options(words({"--device", "lpt:pty:/x", "--out", "a.ply"})));
  EXPECT_FALSE(parse_scan_options(words({"--device", "tcp:h", "--lpt", "tcp:h", "--out", "a.ply"})));
}

// Issue 24: the endpoint grammar of every tool (docs/endpoints.md); an old spelling names the new
// one, and what ldoem-emud offers is taken as it is.
TEST(ScanOptions, Endpoints_TakeTheOneGrammar) {
  const auto old_lpt = parse_scan_options(words({"--device", "tcp:h", "--lpt", "pty:/tmp/x", "--out", "a.ply"}));
  ASSERT_FALSE(old_lpt);
  EXPECT_NE(old_lpt.error().find("--lpt pty:/tmp/x is the old spelling; write --lpt lpt:pty:/tmp/x (docs/endpoints.md)"),
            std::string::npos)
      << old_lpt.error();
  const auto old_device = parse_scan_options(words({"--device", "127.0.0.1:49152", "--out", "a.ply"}));
  ASSERT_FALSE(old_device);
  EXPECT_NE(old_device.error().find("write --device tcp:127.0.0.1:49152"), std::string::npos) << old_device.error();
  const auto offered = parse_scan_options(words({"--device", "serial:pty:/tmp/s", "--out", "a.ply"}));
  ASSERT_TRUE(offered) << offered.error();
  EXPECT_EQ(std::get<driver::SerialEndpoint>(*offered->device).path, "/tmp/s");
}

TEST(ScanOptions, BadValues_AreUsageErrors) {
  for (auto bad : {words({"--speed", "21"}), words({"--speed", "x"}), words({"--format", "text"}),
                   words({"--timeout", "0"}), words({"--timeout", "1e300"}), words({"--step-rate", "1e-300"}), words({"--step-rate", "1e9"}), words({"--optical-offset", "1,2"}), words({"--vertical-resolution", "-1"}),
                   words({"--bogus", "1"}), words({"--out"})}) {
    std::vector<std::string_view> args = bad;
    args.insert(args.begin(), {"--device", "tcp:h"});
    if (args.back() != "--out") {
      args.insert(args.end(), {"--out", "a.ply"});
    }
    EXPECT_FALSE(parse_scan_options(args)) << args[2];
  }
}

TEST(ScanOptions, Help_NeedsNothingElse) {
  auto options = parse_scan_options(words({"--help"}));
  ASSERT_TRUE(options);
  EXPECT_TRUE(options->help);
  EXPECT_NE(scan_usage("ldoem-scan").find("Exit codes"), std::string::npos);
}

TEST(MakePlan, ManyLayersWithoutStepper_IsRefused) {
  auto options = parse_scan_options(words({"--device", "tcp:h", "--out", "a.ply"}));
  ASSERT_TRUE(options);
  EXPECT_FALSE(make_plan(*options));
  options->vertical_apex_deg = 0.0;
  auto plan = make_plan(*options);
  ASSERT_TRUE(plan) << plan.error();
  EXPECT_EQ(plan->layers.layer_count, 1u);
}

TEST(MakePlan, ImpossibleGeometry_IsRefused) {
  auto options = parse_scan_options(words({"--device", "tcp:h", "--lpt", "lpt:pty:/x", "--out", "a.ply",
                                           "--vertical-resolution", "0.1"}));
  ASSERT_TRUE(options);
  EXPECT_FALSE(make_plan(*options));
}

}  // namespace
}  // namespace ldoem::scan
