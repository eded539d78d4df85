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
