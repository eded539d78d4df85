#include "options.hpp"
#include "runner.hpp"
#include "vector_table.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <vector>

namespace ldoem::conformance {
namespace {

base::Expected<SuiteOptions, SuiteUsageError> parse(std::vector<std::string_view> arguments) { return parse_options(arguments); }

TEST(SuiteOptions, TcpEndpoint_ParsesHostAndPort) {
  auto options = parse({"--tcp", "tcp:127.0.0.1:5000"});
  ASSERT_TRUE(options);
  const auto& tcp = std::get<driver::TcpEndpoint>(*options->endpoint);
  EXPECT_EQ(tcp.host, "127.0.0.1");
  EXPECT_EQ(tcp.port, 5000);
  EXPECT_EQ(options->target, Target::emulator);
  EXPECT_EQ(transport_prefix(*options->endpoint), "tcp");
}

TEST(SuiteOptions, CanWithIds_BuildsCanEndpoint) {
  auto options = parse({"--can", "can:vcan0:0x6C2:6C3", "--target=device"});
  ASSERT_TRUE(options);
  const auto& can = std::get<driver::CanEndpoint>(*options->endpoint);
  EXPECT_EQ(can.interface, "vcan0");
  EXPECT_EQ(can.request_id, 0x6C2u);
  EXPECT_EQ(can.response_id, 0x6C3u);
  EXPECT_EQ(options->target, Target::device);
}

TEST(SuiteOptions, SerialAndTimes_AreParsed) {
  auto options = parse({"--serial", "serial:pty:/tmp/ldoem-serial", "--time-scale", "10", "--timeout", "2.5", "--filter", "*/states/*",
                        "--filter", "*S1", "--virtual-time", "-v"});
  ASSERT_TRUE(options);
  EXPECT_EQ(std::get<driver::SerialEndpoint>(*options->endpoint).path, "/tmp/ldoem-serial");
  EXPECT_DOUBLE_EQ(options->time_scale, 10.0);
  EXPECT_EQ(options->reply_timeout, std::chrono::milliseconds(2500));
  EXPECT_EQ(options->filters.size(), 2u);
  EXPECT_TRUE(options->virtual_time);
  EXPECT_TRUE(options->verbose);
}

// The sanitizer builds run the suite without its wall-clock cases (tests/conformance/CMakeLists.txt).
TEST(SuiteOptions, Exclude_LeavesMatchingCasesOutAfterTheFilter) {
  auto table = load_vector_table(embedded_vectors_yaml());
  ASSERT_TRUE(table) << table.error();
  const auto listed = [&](std::vector<std::string_view> arguments) {
    auto options = parse(arguments);
    EXPECT_TRUE(options);
    std::ostringstream out;
    if (options) list_cases(*options, *table, out);
    return out.str();
  };
  const std::string all = listed({"--tcp", "tcp:h"});
  const std::string without_timing = listed({"--tcp", "tcp:h", "--exclude", "*/timing/*"});
  ASSERT_NE(all.find("tcp/timing/"), std::string::npos);
  EXPECT_EQ(without_timing.find("/timing/"), std::string::npos);
  EXPECT_NE(without_timing.find("tcp/states/"), std::string::npos);
  const std::string timing_only = listed({"--tcp", "tcp:h", "--filter", "*/timing/*"});
  // The two halves make up the whole suite, case for case.
  EXPECT_EQ(std::count(all.begin(), all.end(), '\n'),
            std::count(without_timing.begin(), without_timing.end(), '\n') +
                std::count(timing_only.begin(), timing_only.end(), '\n'));
  EXPECT_EQ(listed({"--tcp", "tcp:h", "--filter", "*/timing/*", "--exclude", "*spin_up*"}).find("spin_up"), std::string::npos);
  EXPECT_FALSE(parse({"--tcp", "tcp:h", "--exclude", ""}));
}

TEST(SuiteOptions, TwoEndpoints_AreAUsageError) {
  auto options = parse({"--tcp", "tcp:127.0.0.1", "--serial", "serial:/dev/ttyS0"});
  ASSERT_FALSE(options);
  EXPECT_NE(options.error().message.find("only one"), std::string::npos);
}

TEST(SuiteOptions, NoEndpoint_IsAnErrorUnlessListing) {
  EXPECT_FALSE(parse({}));
  auto listing = parse({"--list"});
  ASSERT_TRUE(listing);
  EXPECT_FALSE(listing->endpoint.has_value());
  EXPECT_TRUE(parse({"--help"}));
}

TEST(SuiteOptions, BadValues_NameTheOption) {
  auto scale = parse({"--tcp", "tcp:h", "--time-scale", "0"});
  ASSERT_FALSE(scale);
  EXPECT_NE(scale.error().message.find("--time-scale"), std::string::npos);
  // Values whose conversion to milliseconds used to overflow (undefined behaviour).
  EXPECT_FALSE(parse({"--tcp", "tcp:h", "--timeout", "1e300"}));
  EXPECT_FALSE(parse({"--tcp", "tcp:h", "--time-scale", "1e-300"}));
  auto target = parse({"--tcp", "tcp:h", "--target", "robot"});
  ASSERT_FALSE(target);
  EXPECT_NE(target.error().message.find("--target"), std::string::npos);
  EXPECT_FALSE(parse({"--tcp"}));
  EXPECT_FALSE(parse({"--can", "can:vcan0:6C0"}));
  EXPECT_FALSE(parse({"--can", "tcp:h"}));
  EXPECT_FALSE(parse({"--tcp", "tcp:h:0"}));  // a host connects to a port; 0 is a listener's
  EXPECT_FALSE(parse({"--tcp", "tcp:h", "--bogus"}));
}

// Issue 24: every spelling from before docs/endpoints.md names the new one.
TEST(SuiteOptions, OldSpellings_NameTheNewOne) {
  const std::vector<std::pair<std::vector<std::string_view>, std::string>> cases{
      {{"--tcp", "127.0.0.1:49152"},
       "--tcp 127.0.0.1:49152 is the old spelling; write --tcp tcp:127.0.0.1:49152 (docs/endpoints.md)"},
      {{"--can", "vcan0"}, "--can vcan0 is the old spelling; write --can can:vcan0 (docs/endpoints.md)"},
      {{"--serial", "/tmp/s"}, "--serial /tmp/s is the old spelling; write --serial serial:/tmp/s (docs/endpoints.md)"},
      {{"--can", "can:vcan0", "--ids", "6C0,6C1"},
       "--ids 6C0,6C1 is the old spelling; write --can can:IF:6C0:6C1 (docs/endpoints.md)"},
  };
  for (const auto& [arguments, message] : cases) {
    auto options = parse(arguments);
    ASSERT_FALSE(options) << message;
    EXPECT_EQ(options.error().message, message);
  }
}

TEST(SuiteOptions, UsageText_ListsEveryOptionAndExitCodes) {
  const std::string text = usage_text("ldoem-conformance");
  for (const char* option : {"--can can:IF", "--tcp tcp:HOST", "--serial serial:", "--target", "--time-scale", "--virtual-time", "--timeout",
                             "--filter", "--list", "--vectors", "--help", "Exit status", "Examples"}) {
    EXPECT_NE(text.find(option), std::string::npos) << option;
  }
}

}  // namespace
}  // namespace ldoem::conformance

namespace ldoem::conformance {
namespace {

TEST(OptionsAgainst, AgainstMasksAndRecord_AreParsed) {
  const std::vector<std::string_view> args{"--tcp", "tcp:127.0.0.1:1", "--against", "c.pcapng", "--mask", "status.*",
                                           "--mask-times", "--record=r.pcapng"};
  const auto options = parse_options(args);
  ASSERT_TRUE(options.has_value()) << options.error().message;
  EXPECT_EQ(options->against, "c.pcapng");
  EXPECT_EQ(options->record, "r.pcapng");
  ASSERT_EQ(options->masks.size(), 1 + kTimeFieldMasks.size());
  EXPECT_EQ(options->masks[0], "status.*");
}

TEST(OptionsAgainst, MaskWithoutAgainst_IsAUsageError) {
  const std::vector<std::string_view> args{"--tcp", "tcp:127.0.0.1:1", "--mask-counters"};
  const auto options = parse_options(args);
  ASSERT_FALSE(options.has_value());
  EXPECT_NE(options.error().message.find("--against"), std::string::npos);
}

}  // namespace
}  // namespace ldoem::conformance
