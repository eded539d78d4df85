// Configuration values SET_CONFIG accepts, the flash image format and its persistence
// (lead decision 2, D4), and the 16-bit clock (lead decision 3).
#include <gtest/gtest.h>

#include "control_test_support.hpp"
#include "ldoem/control/device_clock.hpp"

namespace ldoem::control::test {
namespace {

// The D4 defaults in the version-1 format, verbatim: a change of the format shows here.
constexpr std::string_view kFactoryImage =
    "ldoem-flash 1\n"
    "global 1 10 4\n"
    "interlace 0\n"
    "ethernet 192 168 1 10 255 255 255 0 192 168 1 1 0 0\n"
    "serial 6 0 1 8\n"
    "can 4 1728 1729 0 0\n"
    "filter 0\n"
    "sector 0 3 2160\n"
    "sector 1 1 3600\n"
    "sector 2 0 0\n"
    "sector 3 0 0\n"
    "sector 4 0 0\n"
    "sector 5 0 0\n"
    "sector 6 0 0\n"
    "sector 7 0 0\n"
    "end\n";

protocol::Bytes bytes_of(std::string_view text) { return protocol::Bytes(text.begin(), text.end()); }

TEST(FlashImage, FactoryConfig_SerialisesToTheDocumentedText) {
  EXPECT_EQ(serialise_flash_image(factory_config()), bytes_of(kFactoryImage));
}

TEST(FlashImage, RoundTrip_KeepsEveryField) {
  DeviceConfig config = factory_config();
  config.global = protocol::GlobalConfig{0x10, 15, 1, false};
  config.interlace.mode = 3;
  config.ethernet.node_id = 7;
  config.ethernet.transparent_tcp_port = 49153;
  config.serial = protocol::SerialConfig{2, 1, 2, 7};
  config.can = protocol::CanConfig{1, 0x100, 0x101, 8, 5};
  config.near_field_filter_on = true;
  config.sectors[1] = Sector{0, 0xFFF0};  // S2's not-initialised stop survives
  auto parsed = parse_flash_image(serialise_flash_image(config));
  ASSERT_TRUE(parsed.has_value());
  EXPECT_EQ(*parsed, config);
}

struct CorruptCase {
  const char* name;
  std::string text;
  FlashErrorKind kind;
  std::size_t line;
};

void PrintTo(const CorruptCase& c, std::ostream* os) { *os << c.name; }

std::string replaced(std::string_view from, std::string_view to) {
  std::string text(kFactoryImage);
  text.replace(text.find(from), from.size(), to);
  return text;
}

class CorruptFlash : public ::testing::TestWithParam<CorruptCase> {};

TEST_P(CorruptFlash, IsRefusedWithATypedError) {
  const CorruptCase& c = GetParam();
  auto parsed = parse_flash_image(bytes_of(c.text));
  ASSERT_FALSE(parsed.has_value()) << c.name;
  EXPECT_EQ(parsed.error().kind, c.kind) << c.name << ": " << describe(parsed.error().kind);
  EXPECT_EQ(parsed.error().line, c.line) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CorruptFlash,
    ::testing::Values(
        CorruptCase{"empty", "", FlashErrorKind::empty, 0},
        CorruptCase{"other_file", "hello\n", FlashErrorKind::bad_magic, 1},
        CorruptCase{"future_version", replaced("ldoem-flash 1", "ldoem-flash 2"), FlashErrorKind::unsupported_version, 1},
        CorruptCase{"truncated", std::string(kFactoryImage.substr(0, 100)), FlashErrorKind::malformed_line, 5},
        // fuzz_flash_image: a leading zero is not what serialise_flash_image writes.
        CorruptCase{"leading_zero", replaced("global 1 10 4", "global 1 010 4"), FlashErrorKind::malformed_line, 2},
        CorruptCase{"missing_end", replaced("end\n", ""), FlashErrorKind::malformed_line, 16},
        CorruptCase{"record_order", replaced("interlace 0\nethernet", "ethernet"), FlashErrorKind::malformed_line, 3},
        CorruptCase{"not_a_number", replaced("global 1 10 4", "global 1 1x 4"), FlashErrorKind::malformed_line, 2},
        CorruptCase{"double_space", replaced("global 1 10 4", "global 1  10 4"), FlashErrorKind::malformed_line, 2},
        CorruptCase{"extra_field", replaced("filter 0", "filter 0 0"), FlashErrorKind::malformed_line, 7},
        CorruptCase{"over_a_word", replaced("can 4 1728", "can 4 65536"), FlashErrorKind::value_out_of_range, 6},
        CorruptCase{"filter_two", replaced("filter 0", "filter 2"), FlashErrorKind::value_out_of_range, 7},
        CorruptCase{"sector_number", replaced("sector 3 0 0", "sector 4 0 0"), FlashErrorKind::malformed_line, 11},
        CorruptCase{"speed_refused", replaced("global 1 10 4", "global 1 30 4"), FlashErrorKind::value_out_of_range, 0},
        CorruptCase{"reserved_function", replaced("sector 2 0 0", "sector 2 2 0"), FlashErrorKind::value_out_of_range, 0},
        CorruptCase{"trailing", std::string(kFactoryImage) + "x\n", FlashErrorKind::trailing_data, 17}),
    [](const ::testing::TestParamInfo<CorruptCase>& info) { return std::string(info.param.name); });

TEST(FlashStore, CorruptStore_FallsBackToDefaultsAndSaysWhy) {
  MemoryFlashStore store;
  ASSERT_TRUE(store.save(bytes_of("garbage")));
  const FlashLoadResult result = load_flash_or(store, factory_config());
  EXPECT_EQ(result.config, factory_config());
  ASSERT_TRUE(result.problem.has_value());
  EXPECT_EQ(result.problem->kind, FlashErrorKind::bad_magic);
}

TEST(FlashPersistence, FlashWritesSurviveARestartOfTheDaemon) {
  MemoryFlashStore store;
  {
    Bench bench;
    bench.request(kTcp1, "SET_FUNCTION 0000 0003 0800 0001");  // flash
    bench.request(kTcp1, "SET_FUNCTION 0001 0001 0a00 0000");  // RAM only
    bench.request(kTcp1, "SET_CONFIG 0001 0003 0001 0002 0007");
    ASSERT_FALSE(bench.flash_writes.empty());
    ASSERT_TRUE(store.save(bench.flash_writes.back()));
  }
  const FlashLoadResult loaded = load_flash_or(store, factory_config());
  ASSERT_FALSE(loaded.problem.has_value());
  ControlUnit::Setup setup;
  setup.flash = loaded.config;
  Bench restarted(setup);
  EXPECT_EQ(restarted.reply_text(kTcp1, "GET_FUNCTION 0000"), "GET_FUNCTION reply 0000 0003 0800");
  EXPECT_EQ(restarted.reply_text(kTcp1, "GET_FUNCTION 0001"), "GET_FUNCTION reply 0001 0001 0e10");
  EXPECT_EQ(restarted.reply_text(kTcp1, "GET_CONFIG 0001"), "GET_CONFIG reply 0001 0003 0001 0002 0007");
}

TEST(FlashPersistence, SetConfigGlobal_CommitsTheRamSectorTable) {
  // S1's observation (spec 3.3): sectors sent with FLASHFLAG 0 become permanent only when a
  // SET_CONFIG(global) follows.
  Bench bench;
  bench.request(kTcp1, "SET_FUNCTION 0000 0003 10e0 0000");
  EXPECT_TRUE(bench.flash_writes.empty());
  bench.request(kTcp1, "DO_RESET 0000");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_FUNCTION 0000"), "GET_FUNCTION reply 0000 0003 0870");
  bench.request(kTcp1, "SET_FUNCTION 0000 0003 10e0 0000");
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_CONFIG 0010 0001 000a 0004"), "SET_CONFIG reply 0000");
  ASSERT_EQ(bench.flash_writes.size(), 1u);
  bench.request(kTcp1, "DO_RESET 0000");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_FUNCTION 0000"), "GET_FUNCTION reply 0000 0003 10e0");
  auto image = parse_flash_image(bench.flash_writes.back());
  ASSERT_TRUE(image.has_value());
  EXPECT_EQ(image->sectors[0], (Sector{3, 0x10E0}));
}

TEST(FlashPersistence, UnchangedFlash_IsNotRewritten) {
  Bench bench;
  bench.request(kTcp1, "SET_CONFIG 0010 0001 000a 0004");  // same as the defaults
  bench.request(kTcp1, "SET_FILTER 0001 0000");
  EXPECT_TRUE(bench.flash_writes.empty());
  bench.request(kTcp1, "SET_FILTER 0001 0001");
  EXPECT_EQ(bench.flash_writes.size(), 1u);
}

// A flash store that refuses every write (the daemon's file store with its folder gone).
class RefusingFlashStore final : public FlashStore {
 public:
  protocol::Bytes load() const override { return {}; }
  Saved save(protocol::ByteView) override {
    ++attempts;
    return base::Unexpected(std::string("refused"));
  }
  int attempts = 0;
};

// L-flash-1: a flash write that is not stored is never answered as a success, and changes
// neither RAM nor flash: each service answers its own error, SET_FILTER (which has none) reason 6.
TEST(FlashPersistence, AWriteTheStoreRefuses_IsAnsweredAsAnErrorAndChangesNothing) {
  RefusingFlashStore store;
  ControlUnit::Setup setup;
  setup.flash_store = &store;
  Bench bench(setup);
  const DeviceState before = bench.unit.state();
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_CONFIG 0010 0001 000c 0004"), "SET_CONFIG reply 0001");
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_FILTER 0001 0001"), "SERVICE_FAILURE 0209 0006");
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_FUNCTION 0000 0003 0800 0001"), "SET_FUNCTION reply ffff");
  EXPECT_EQ(store.attempts, 3);
  EXPECT_TRUE(bench.flash_writes.empty());
  EXPECT_EQ(bench.unit.state(), before);
  // What needs no flash still works: a SET_CONFIG that changes nothing, and a RAM-only sector.
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_CONFIG 0010 0001 000a 0004"), "SET_CONFIG reply 0000");
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_FUNCTION 0000 0003 0800 0000"), "SET_FUNCTION reply 0000");
  EXPECT_EQ(store.attempts, 3);
}

TEST(SetFunction, InvalidRequests_AnswerFFFFAndChangeNothing) {
  for (const char* request : {"SET_FUNCTION 0008 0003 0800 0000", "SET_FUNCTION 0000 0002 0800 0000",
                              "SET_FUNCTION 0000 0005 0800 0000", "SET_FUNCTION 0000 0003 1688 0000",
                              "SET_FUNCTION 0001 0001 fff0 0001"}) {
    Bench bench;
    EXPECT_EQ(bench.reply_text(kTcp1, request), "SET_FUNCTION reply ffff") << request;
    EXPECT_EQ(bench.unit.state(), power_up_state(SimTime{}, factory_config())) << request;
  }
}

TEST(SetFunction, NotInitialisedWithAnyStop_IsAcceptedAsS2SendsIt) {
  Bench bench;
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_FUNCTION 0001 0000 fff0 0001"), "SET_FUNCTION reply 0001");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_FUNCTION 0001"), "GET_FUNCTION reply 0001 0000 fff0");
}

struct ConfigCase {
  const char* request;
  const char* reply;
};

void PrintTo(const ConfigCase& c, std::ostream* os) { *os << c.request; }

class SetConfigValues : public ::testing::TestWithParam<ConfigCase> {};

TEST_P(SetConfigValues, AcceptOrRefuseInBand) {
  Bench bench;
  EXPECT_EQ(bench.reply_text(kTcp1, GetParam().request), GetParam().reply);
}

INSTANTIATE_TEST_SUITE_P(
    Keys, SetConfigValues,
    ::testing::Values(
        ConfigCase{"SET_CONFIG 0010 0001 000a 0008", "SET_CONFIG reply 0000"},
        ConfigCase{"SET_CONFIG 0010 0010 000a 0008 0000", "SET_CONFIG reply 0000"},  // S2's padding
        ConfigCase{"SET_CONFIG 0010 0000 000a 0008", "SET_CONFIG reply 0001"},        // id 0
        ConfigCase{"SET_CONFIG 0010 00ff 000a 0008", "SET_CONFIG reply 0001"},        // id 255
        ConfigCase{"SET_CONFIG 0010 0001 0004 0008", "SET_CONFIG reply 0001"},        // 4 Hz
        ConfigCase{"SET_CONFIG 0010 0001 0015 0008", "SET_CONFIG reply 0001"},        // 21 Hz
        ConfigCase{"SET_CONFIG 0010 0001 000a 0007", "SET_CONFIG reply 0001"},        // 7 does not divide 5760
        ConfigCase{"SET_CONFIG 0010 0001 000a 0000", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0010 0001 000a 0001", "SET_CONFIG reply 0001"},        // 1 tick needs interlace
        ConfigCase{"SET_CONFIG 0010 0001 000a 0003", "SET_CONFIG reply 0000"},        // 3 divides 5760
        ConfigCase{"SET_CONFIG 0011 0003", "SET_CONFIG reply 0000"},
        ConfigCase{"SET_CONFIG 0011 0010", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0005 00c0 00a8 0001 000a 00ff 00ff 00ff 0000 00c0 00a8 0001 0001 0000 0000",
                   "SET_CONFIG reply 0000"},
        ConfigCase{"SET_CONFIG 0005 0100 00a8 0001 000a 00ff 00ff 00ff 0000 00c0 00a8 0001 0001 0000 0000",
                   "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0001 0006 0000 0001 0008", "SET_CONFIG reply 0000"},  // S2's 115200 8N1
        ConfigCase{"SET_CONFIG 0001 0007 0000 0001 0008", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0001 0006 0003 0001 0008", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0001 0006 0000 0003 0008", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0001 0006 0000 0001 0009", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0002 0004 06c0 06c1 0000 0000", "SET_CONFIG reply 0000"},
        ConfigCase{"SET_CONFIG 0002 0005 06c0 06c1 0000 0000", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0002 0004 0800 06c1 0000 0000", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0002 0004 06c0 06c0 0000 0000", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0002 0004 06c0 06c1 0100 0000", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0002 0004 06c0 06c1 0000 0080", "SET_CONFIG reply 0001"},
        ConfigCase{"SET_CONFIG 0003 0000", "SET_CONFIG reply 0001"},  // no layout (D2 in-band)
        ConfigCase{"SET_CONFIG 0010 0001 000a", "SERVICE_FAILURE 0201 0002"}));

TEST(SetConfig, OneTickStep_NeedsInterlaceFirstAndKeepsIt) {
  Bench bench;  // S4's order: interlace 3, then 0.0625 deg
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_CONFIG 0011 0003"), "SET_CONFIG reply 0000");
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_CONFIG 0010 0001 0005 0001"), "SET_CONFIG reply 0000");
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_CONFIG 0011 0000"), "SET_CONFIG reply 0001");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_CONFIG 0011"), "GET_CONFIG reply 0011 0003");
}

TEST(DeviceClock, WrapsAt65536AndFollowsSimulatedTime) {
  DeviceClock clock = DeviceClock::reading(SimTime(0), 0);
  EXPECT_EQ(clock.value_at(SimTime(65'535'999'999)), 65535);
  EXPECT_EQ(clock.value_at(SimTime(65'536'000'000)), 0);
  clock.set(SimTime(1'000'500'000), 65530);  // 1000.5 ms
  EXPECT_EQ(clock.value_at(SimTime(1'000'999'999)), 65530);
  EXPECT_EQ(clock.value_at(SimTime(1'010'000'000)), 4);
  clock.add(-10);
  EXPECT_EQ(clock.value_at(SimTime(1'010'000'000)), 65530);
  clock.add(20);
  EXPECT_EQ(clock.value_at(SimTime(1'010'000'000)), 14);
  EXPECT_EQ(floor_ms(SimTime(-1)), -1);
}

TEST(DeviceClock, SetTimeServices_ReplyTheNewValueAcrossTheWrap) {
  Bench bench;
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_TIME_ABS fffa"), "SET_TIME_ABS reply fffa");
  bench.advance_by(SimTime(10ms));
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_SYNC_CLOCK"), "GET_SYNC_CLOCK reply 0004");
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_TIME_REL fff6"), "SET_TIME_REL reply fffa");  // -10
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_TIME_REL 7fff"), "SET_TIME_REL reply 7ff9");
}

}  // namespace
}  // namespace ldoem::control::test
