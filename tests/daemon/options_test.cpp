// Options parsing table (design.md convention 1): every option, its default, and the usage errors.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "ldoem/daemon/options.hpp"

namespace ldoem::daemon {
namespace {

base::Expected<Command, UsageError> parse(std::vector<std::string_view> arguments) {
  return parse_command_line(arguments);
}

Options run_options(std::vector<std::string_view> arguments) {
  const auto command = parse(arguments);
  EXPECT_TRUE(command.has_value()) << (command ? "" : command.error().message);
  if (!command) return {};
  EXPECT_EQ(command->kind, CommandKind::run);
  return command->options;
}

TEST(Options, ControlAndEventLog_OffByDefaultAndTakeAPath) {
  const Options plain = run_options({"--scene", "s.yaml"});
  EXPECT_FALSE(plain.control_path);
  EXPECT_FALSE(plain.event_log_path);
  const Options options = run_options({"--scene", "s.yaml", "--control", "/tmp/x.ctl", "--event-log=/tmp/e.log"});
  EXPECT_EQ(options.control_path, std::filesystem::path("/tmp/x.ctl"));
  EXPECT_EQ(options.event_log_path, std::filesystem::path("/tmp/e.log"));
  const auto bad = parse({"--scene", "s.yaml", "--control", ""});
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("--control"), std::string::npos);
}

TEST(Options, Realtime_OffByDefaultAndAFlag) {
  EXPECT_FALSE(run_options({"--scene", "s.yaml"}).realtime);
  EXPECT_TRUE(run_options({"--scene", "s.yaml", "--realtime"}).realtime);
}

TEST(Options, SceneOnly_GivesEveryDefault) {
  const Options options = run_options({"--scene", "scenes/minimal.yaml"});
  EXPECT_EQ(options.scene_path, "scenes/minimal.yaml");
  EXPECT_EQ(options.can_interface, std::optional<std::string>("vcan0"));
  EXPECT_TRUE(options.can_id_pairs.empty());
  EXPECT_FALSE(options.tcp.has_value());
  EXPECT_FALSE(options.serial_pty.has_value());
  EXPECT_FALSE(options.lpt.has_value());
  EXPECT_EQ(options.flash_mode, FlashMode::file);
  EXPECT_EQ(options.flash_path, default_flash_folder() / "minimal.yaml.flash");  // never beside the scene
  EXPECT_EQ(options.time_scale, 1.0);
  EXPECT_FALSE(options.virtual_time);
  EXPECT_FALSE(options.seed.has_value());
  EXPECT_EQ(options.log_level, LogLevel::warn);
  EXPECT_FALSE(options.count_profiles.has_value());
  EXPECT_FALSE(options.timeout_s.has_value());
}

TEST(Options, EveryValueOption_IsStored) {
  const Options options = run_options({"--scene=s.yaml", "--can", "can:vcan1:6C0:6C1", "--can",
                                       "can:vcan1:0x6C2:0x6C3", "--tcp", "tcp:127.0.0.1:0", "--serial", "serial:pty:/tmp/s", "--lpt",
                                       "lpt:pty:/tmp/l", "--flash", "/tmp/f", "--time-scale", "2.5", "--seed", "42",
                                       "--log-level", "debug", "--count-profiles", "3", "--timeout", "1.5",
                                       "--virtual-time"});
  EXPECT_EQ(options.scene_path, "s.yaml");
  EXPECT_EQ(options.can_interface, std::optional<std::string>("vcan1"));
  ASSERT_EQ(options.can_id_pairs.size(), 2u);
  EXPECT_EQ(options.can_id_pairs[0], (CanIdPair{0x6C0, 0x6C1}));
  EXPECT_EQ(options.can_id_pairs[1], (CanIdPair{0x6C2, 0x6C3}));
  EXPECT_EQ(options.tcp, (std::optional<TcpOption>(TcpOption{"127.0.0.1", 0})));
  EXPECT_EQ(options.serial_pty, std::optional<std::filesystem::path>("/tmp/s"));
  EXPECT_EQ(options.lpt, (std::optional<LptOption>(LptOption{LptBackend::pty, "/tmp/l"})));
  EXPECT_EQ(options.flash_path, "/tmp/f");
  EXPECT_EQ(options.time_scale, 2.5);
  EXPECT_TRUE(options.virtual_time);
  EXPECT_EQ(options.seed, std::optional<std::uint64_t>(42));
  EXPECT_EQ(options.log_level, LogLevel::debug);
  EXPECT_EQ(options.count_profiles, std::optional<std::uint64_t>(3));
  EXPECT_EQ(options.timeout_s, std::optional<double>(1.5));
}

TEST(Options, RecordOptions_AreStoredAndChecked) {
  const Options options = run_options({"--scene", "s.yaml", "--record", "c.pcapng", "--record-max-mb", "2",
                                       "--record-files", "3"});
  EXPECT_EQ(options.record_path, std::filesystem::path("c.pcapng"));
  EXPECT_EQ(options.record_max_bytes, 2u * 1024 * 1024);
  EXPECT_EQ(options.record_files, 3u);
  EXPECT_FALSE(run_options({"--scene", "s.yaml"}).record_path.has_value());
  EXPECT_FALSE(parse({"--scene", "s.yaml", "--record-files", "0"}).has_value());
  EXPECT_FALSE(parse({"--scene", "s.yaml", "--record-max-mb", "-1"}).has_value());
}

TEST(Options, TcpWithoutPort_UsesServicePort49152) {
  EXPECT_EQ(run_options({"--scene", "s", "--tcp", "tcp:0.0.0.0"}).tcp, (std::optional<TcpOption>(TcpOption{"0.0.0.0", 49152})));
}

TEST(Options, NoCanAndNoFlash_AreApplied) {
  const Options options = run_options({"--scene", "s", "--no-can", "--tcp", "tcp:127.0.0.1", "--no-flash"});
  EXPECT_FALSE(options.can_interface.has_value());
  EXPECT_EQ(options.flash_mode, FlashMode::memory);
  EXPECT_TRUE(options.flash_path.empty());
}

TEST(Options, LptGpio_IsParsed) {
  EXPECT_EQ(run_options({"--scene", "s", "--lpt", "lpt:gpio:ldoem-lpt"}).lpt,
            (std::optional<LptOption>(LptOption{LptBackend::gpio, "ldoem-lpt"})));
}

TEST(Options, HelpAndVersion_WinOverEverythingElse) {
  EXPECT_EQ(parse({"--bogus", "--help"}).has_value(), false);  // parsed left to right: the bogus option first
  EXPECT_EQ(parse({"--help"})->kind, CommandKind::help);
  EXPECT_EQ(parse({"-h"})->kind, CommandKind::help);
  EXPECT_EQ(parse({"--help-all"})->kind, CommandKind::help_all);
  EXPECT_EQ(parse({"--version"})->kind, CommandKind::version);
}

struct BadCase {
  std::vector<std::string_view> arguments;
  std::string_view message_starts_with;
};

TEST(Options, BadCommandLines_AreUsageErrorsNamingTheOption) {
  const std::vector<BadCase> cases{
      {{}, "--scene: required"},
      {{"--scene"}, "--scene: needs a value"},
      {{"--scene", "s", "--frobnicate"}, "unknown option `--frobnicate`"},
      {{"--scene", "s", "--time-scale", "0"}, "--time-scale: must be a number from 1e-6 to 1e6"},
      {{"--scene", "s", "--time-scale", "-1"}, "--time-scale: must be a number from 1e-6 to 1e6"},
      {{"--scene", "s", "--time-scale", "fast"}, "--time-scale: must be a number from 1e-6 to 1e6"},
      {{"--scene", "s", "--time-scale", "inf"}, "--time-scale: must be a number from 1e-6 to 1e6"},
      {{"--scene", "s", "--can", "can:vcan0:6C0"}, "--can: endpoint `can:vcan0:6C0`: missing field"},
      {{"--scene", "s", "--can", "can:vcan0:800:6C1"}, "--can: endpoint `can:vcan0:800:6C1`: out of range"},
      {{"--scene", "s", "--can", "can:vcan0:6C0:6C0"}, "--can: endpoint `can:vcan0:6C0:6C0`: out of range: request and"},
      {{"--scene", "s", "--can", "can:vcan0:6C0:6C1", "--can", "can:vcan0:6C1:6C2"}, "--can: every identifier"},
      {{"--scene", "s", "--can", "can:vcan0:6C0:6C1", "--can", "can:vcan1:6C2:6C3"}, "--can: every --can names the same"},
      {{"--scene", "s", "--can", "can:isotp:vcan0"}, "--can: endpoint `can:isotp:vcan0`: wrong side"},
      // Issue 24: every spelling from before docs/endpoints.md names the new one.
      {{"--scene", "s", "--can-ids", "6C0:6C1"},
       "--can-ids 6C0:6C1 is the old spelling; write --can can:IF:6C0:6C1 (docs/endpoints.md)"},
      {{"--scene", "s", "--can", "vcan0"}, "--can vcan0 is the old spelling; write --can can:vcan0 (docs/endpoints.md)"},
      {{"--scene", "s", "--tcp", "127.0.0.1:49152"},
       "--tcp 127.0.0.1:49152 is the old spelling; write --tcp tcp:127.0.0.1:49152 (docs/endpoints.md)"},
      {{"--scene", "s", "--serial", "pty:/x"}, "--serial pty:/x is the old spelling; write --serial serial:pty:/x (docs/endpoints.md)"},
      {{"--scene", "s", "--lpt", "pty:/x"}, "--lpt pty:/x is the old spelling; write --lpt lpt:pty:/x (docs/endpoints.md)"},
      {{"--scene", "s", "--lpt", "gpio:c"}, "--lpt gpio:c is the old spelling; write --lpt lpt:gpio:c (docs/endpoints.md)"},
      {{"--scene", "s", "--no-can", "--can", "can:vcan0", "--tcp", "tcp:h"}, "--no-can: conflicts with --can"},
      {{"--scene", "s", "--no-can", "--can", "can:vcan0:6C0:6C1", "--tcp", "tcp:h"}, "--no-can: conflicts with --can"},
      {{"--scene", "s", "--flash", "f", "--no-flash"}, "--no-flash: conflicts with --flash"},
      {{"--scene", "s", "--reset-flash", "--no-flash", "--tcp", "tcp:h"}, "--reset-flash: conflicts with --no-flash"},
      {{"--scene", "s", "--realtime", "--virtual-time"}, "--realtime: conflicts with --virtual-time"},
      {{"--scene", "s", "--flash-dir", "d", "--flash", "f"}, "--flash-dir: conflicts with --flash"},
      {{"--scene", "s", "--no-flash", "--flash-dir", "d", "--tcp", "tcp:h"}, "--flash-dir: conflicts with --no-flash"},
      {{"--scene", "s", "--flash-dir", ""}, "--flash-dir: expects a folder"},
      {{"--scene", "s", "--tcp", ":49152"}, "--tcp: endpoint `:49152`: unknown scheme: expected tcp:HOST[:PORT]"},
      {{"--scene", "s", "--tcp", "tcp::49152"}, "--tcp: endpoint `tcp::49152`: missing field: no host"},
      {{"--scene", "s", "--tcp", "tcp:h:70000"}, "--tcp: endpoint `tcp:h:70000`: out of range: port must be 0..65535"},
      {{"--scene", "s", "--tcp", "can:vcan0"}, "--tcp: endpoint `can:vcan0`: wrong kind: expected tcp:HOST[:PORT]"},
      {{"--scene", "s", "--serial", "serial:/dev/ttyS0"}, "--serial: endpoint `serial:/dev/ttyS0`: wrong side"},
      {{"--scene", "s", "--lpt", "parport:/dev/parport0"}, "--lpt: endpoint `parport:/dev/parport0`: unknown scheme"},
      {{"--scene", "s", "--lpt", "lpt:/dev/parport0"}, "--lpt: endpoint `lpt:/dev/parport0`: wrong side"},
      {{"--scene", "s", "--lpt", "lpt:pty:"}, "--lpt: endpoint `lpt:pty:`: missing field"},
      {{"--scene", "s", "--seed", "-3"}, "--seed: must be an unsigned integer"},
      {{"--scene", "s", "--log-level", "verbose"}, "--log-level: must be error, warn, info or debug"},
      {{"--scene", "s", "--count-profiles", "0"}, "--count-profiles: must be an integer > 0"},
      {{"--scene", "s", "--timeout", "0"}, "--timeout: must be a number of seconds > 0"},
      // Issue 11: out of range, the conversion to nanoseconds or bytes would overflow (UB).
      {{"--scene", "s", "--timeout", "1e300"}, "--timeout: must be a number of seconds > 0 and at most 1e9"},
      {{"--scene", "s", "--timeout", "1.1e9"}, "--timeout: must be a number of seconds > 0 and at most 1e9"},
      {{"--scene", "s", "--time-scale", "1e-300"}, "--time-scale: must be a number from 1e-6 to 1e6"},
      {{"--scene", "s", "--time-scale", "2e6"}, "--time-scale: must be a number from 1e-6 to 1e6"},
      {{"--scene", "s", "--record-max-mb", "1e300"}, "--record-max-mb: must be a number > 0 and at most 1048576"},
      // Issue 27 D4: 10 million files made every rotation rename 10 million slots.
      {{"--scene", "s", "--record-files", "1001"}, "--record-files: must be an integer in [1, 1000]"},
      {{"--scene", "s", "--record-files", "4294967295"}, "--record-files: must be an integer in [1, 1000]"},
      {{"--scene", "s", "--no-flash=1"}, "--no-flash: takes no value"},
      {{"--scene", "s", "--inter-byte-timeout", "-1"}, "--inter-byte-timeout: must be a number of milliseconds"},
      {{"--scene", "s", "--tcp-idle-timeout", "1e300"}, "--tcp-idle-timeout: must be a number of seconds"},
      {{"--scene", "s", "--tcp-silent-timeout", "soon"}, "--tcp-silent-timeout: must be a number of seconds"},
      {{"--scene", "s", "--max-clients", "0"}, "--max-clients: must be an integer from 1 to 100000"},
      {{"--scene", "s", "--max-clients", "-4"}, "--max-clients: must be an integer from 1 to 100000"},
      {{"--scene", "s", "--max-clients", "100001"}, "--max-clients: must be an integer from 1 to 100000"},
      {{"--scene", "s", "--max-clients", "many"}, "--max-clients: must be an integer from 1 to 100000"},
  };
  for (const BadCase& bad : cases) {
    const auto command = parse(bad.arguments);
    ASSERT_FALSE(command.has_value()) << "accepted: " << bad.message_starts_with;
    EXPECT_EQ(command.error().message.substr(0, bad.message_starts_with.size()), bad.message_starts_with)
        << command.error().message;
  }
}

TEST(Options, HostLimits_HaveDefaultsAndOptions) {
  const auto defaults = parse({"--scene", "s"});
  ASSERT_TRUE(defaults.has_value());
  EXPECT_EQ(defaults->options.host_limits, endpoints::HostLimits{});
  EXPECT_EQ(defaults->options.host_limits.inter_byte_timeout, std::chrono::milliseconds(500));
  EXPECT_EQ(defaults->options.host_limits.silent_timeout, std::chrono::milliseconds(60000));
  EXPECT_EQ(defaults->options.host_limits.idle_timeout, std::chrono::milliseconds(0));
  EXPECT_EQ(defaults->options.host_limits.max_tcp_clients, 64u);
  const auto set = parse({"--scene", "s", "--inter-byte-timeout", "250", "--tcp-silent-timeout", "0",
                          "--tcp-idle-timeout", "1.5", "--max-clients", "3"});
  ASSERT_TRUE(set.has_value()) << set.error().message;
  EXPECT_EQ(set->options.host_limits.inter_byte_timeout, std::chrono::milliseconds(250));
  EXPECT_EQ(set->options.host_limits.silent_timeout, std::chrono::milliseconds(0));
  EXPECT_EQ(set->options.host_limits.idle_timeout, std::chrono::milliseconds(1500));
  EXPECT_EQ(set->options.host_limits.max_tcp_clients, 3u);
}

TEST(Options, FlashDir_PutsTheFlashBesideNoScene_UnderTheSameName) {
  EXPECT_EQ(run_options({"--scene", "scenes/minimal.yaml", "--flash-dir", "/var/lib/x"}).flash_path,
            "/var/lib/x/minimal.yaml.flash");
  EXPECT_EQ(run_options({"--scene", "minimal.yaml", "--flash-dir", "state"}).flash_path, "state/minimal.yaml.flash");
  EXPECT_EQ(flash_folder(run_options({"--scene", "scenes/minimal.yaml"})), default_flash_folder());
}

// Issue 24: the flash goes to a state folder, never beside the scene (a clone's scenes/ or
// /usr/share/ldoem/scenes): the unit's StateDirectory, else XDG's state home.
TEST(Options, DefaultFlashFolder_IsTheUnitsStateDirectoryElseXdgStateHome) {
  const auto from = [](std::map<std::string, std::string> variables) {
    return default_flash_folder([variables](const char* name) -> const char* {
      const auto found = variables.find(name);
      return found == variables.end() ? nullptr : found->second.c_str();
    });
  };
  EXPECT_EQ(from({{"STATE_DIRECTORY", "/var/lib/ldoem-emud:/var/lib/other"}, {"XDG_STATE_HOME", "/x"}, {"HOME", "/h"}}),
            "/var/lib/ldoem-emud");
  EXPECT_EQ(from({{"XDG_STATE_HOME", "/x/state"}, {"HOME", "/h"}}), "/x/state/ldoem");
  EXPECT_EQ(from({{"XDG_STATE_HOME", "relative"}, {"HOME", "/h"}}), "/h/.local/state/ldoem");  // XDG: ignored
  EXPECT_EQ(from({{"HOME", "/h"}}), "/h/.local/state/ldoem");
  EXPECT_EQ(from({}), "");
  EXPECT_NE(run_options({"--scene", "scenes/minimal.yaml"}).flash_path.parent_path(), "scenes");
}

TEST(Options, UsageText_ListsEveryOptionExitCodesAndExamples) {
  const std::string text = usage_text("ldoem-emud");
  for (const char* needle : {"--scene", "--can can:IF[:REQ:RESP]", "--no-can", "--tcp tcp:HOST", "--serial serial:pty:", "--serial", "--lpt lpt:pty:",
                             "--lpt lpt:gpio:", "--flash", "--flash-dir", "--no-flash", "--time-scale", "--virtual-time", "--seed",
                             "--log-level", "--count-profiles", "--timeout", "--help", "--version", "[can:vcan0",
                             "--reset-flash", "--inter-byte-timeout", "--tcp-silent-timeout", "--tcp-idle-timeout",
                             "--max-clients N", "[64]",
                             "[STATE/<scene>.flash", "49152", "128+N", "  2  ", "Examples:",
                             "ldoem-emud --scene scenes/corridor.yaml --can can:vcan0 --lpt lpt:pty:/tmp/ldoem-lpt"}) {
    EXPECT_NE(text.find(needle), std::string::npos) << needle;
  }
}

}  // namespace
}  // namespace ldoem::daemon
