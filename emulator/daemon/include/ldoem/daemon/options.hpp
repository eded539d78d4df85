// The command line of ldoem-emud, parsed into a plain Options value by a pure function
// (design.md convention 1: main is a short script; everything it decides is reachable by a test).
#pragma once

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/base/endpoint.hpp"
#include "ldoem/endpoints/can_id_pair.hpp"
#include "ldoem/endpoints/host_limits.hpp"
#include "ldoem/endpoints/logger.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/transport.hpp"

namespace ldoem::daemon {

// Exit codes (design.md convention 1, as can-utils' candump): --help documents them.
inline constexpr int kExitOk = 0;
inline constexpr int kExitRuntimeFailure = 1;
inline constexpr int kExitUsageError = 2;  // bad option, bad scene, unusable transport setup
inline constexpr int kExitSignalBase = 128;  // + SIGINT / SIGTERM number

inline constexpr std::string_view kDefaultCanInterface = "vcan0";
inline constexpr std::string_view kFlashFileSuffix = ".flash";  // D4: <scene>.flash

// Ranges of the numeric options (issue 11): inside them every conversion to int64 nanoseconds
// or bytes is exact and far from overflow (a bigger --timeout or a smaller --time-scale was
// undefined behaviour in that conversion); outside them the option is refused (exit 2).
inline constexpr double kMaxTimeoutSeconds = 1e9;         // about 31 years (int64 ns: 292)
inline constexpr double kMinTimeScale = 1e-6;             // a simulated second per 11.6 wall days
inline constexpr double kMaxTimeScale = 1e6;              // 11.6 simulated days per wall second
inline constexpr double kMaxRecordMegabytes = 1024.0 * 1024.0;  // 1 TiB per capture file
// Rotation renames up to this many files (on a worker thread, issue 27 D4).
inline constexpr unsigned kMaxRecordFiles = 1000;
inline constexpr double kMaxHostTimeoutSeconds = 1e6;     // the host timeouts: 11.6 days
inline constexpr std::size_t kMaxTcpClients = 100'000;    // --max-clients (descriptors bound it sooner)

using endpoints::CanIdPair;
using endpoints::LogLevel;

struct TcpOption {
  std::string address;
  std::uint16_t port = base::kHostTcpPort;  // 0 = any free port (printed on stdout)
  bool operator==(const TcpOption&) const = default;
};

// The daemon offers a port as pty or gpio: parse_offered_endpoint refuses ppdev (host side only).
using base::LptBackend;

struct LptOption {
  LptBackend backend = LptBackend::pty;
  std::string target;  // pty: symlink path to create; gpio: chip path, name or label
  bool operator==(const LptOption&) const = default;
};

enum class FlashMode : std::uint8_t { file, memory };

struct Options {
  std::filesystem::path scene_path;
  std::optional<std::string> can_interface = std::string(kDefaultCanInterface);  // empty: --no-can
  // Empty: one pair, taken from the flash's CAN configuration (D1 defaults 0x6C0/0x6C1).
  std::vector<CanIdPair> can_id_pairs;
  std::optional<TcpOption> tcp;
  std::optional<std::filesystem::path> serial_pty;  // symlink path of the serial pty
  std::optional<LptOption> lpt;
  FlashMode flash_mode = FlashMode::file;
  std::filesystem::path flash_path;  // resolved: --flash FILE or <scene>.flash
  // --flash-dir DIR: the flash files default to DIR instead of the scene's folder, with the
  // same names (<scene>.flash, <scene>.<name>.flash, a relative flash_file): a service keeps
  // them in its state directory while the scene stays read-only (issue 15, docs/scaling.md).
  std::optional<std::filesystem::path> flash_dir;
  // --reset-flash: start from the scene's defaults even when the flash file cannot be read or
  // parsed (it is replaced at the first flash write and at exit). Without it that is exit 2.
  bool reset_flash = false;
  double time_scale = 1.0;
  bool virtual_time = false;
  bool realtime = false;  // --realtime: SCHED_FIFO and mlockall when permitted (realtime.hpp)
  std::optional<std::uint64_t> seed;  // overrides the scene's seed
  LogLevel log_level = LogLevel::warn;
  std::optional<std::uint64_t> count_profiles;  // stop (exit 0) after this many profiles
  std::optional<double> timeout_s;              // stop (exit 0) after this many wall seconds
  // --record FILE: every telegram on every transport into a pcapng capture (docs/capture.md),
  // rotated at record_max_bytes (0: no cap) keeping record_files files.
  std::optional<std::filesystem::path> record_path;
  std::uint64_t record_max_bytes = 0;
  unsigned record_files = 10;
  // --inter-byte-timeout, --tcp-silent-timeout, --tcp-idle-timeout (issue 11, docs/emulator.md).
  endpoints::HostLimits host_limits;
  std::optional<std::filesystem::path> control_path;    // --control: the control socket (D11)
  std::optional<std::filesystem::path> event_log_path;  // --event-log: fault and state events
  // --replay CAPTURE: serve the device recorded in CAPTURE, no scene (docs/replay.md); which of
  // its transports (default: the busiest) and the device's TCP port in it (default: detected).
  std::optional<std::filesystem::path> replay_path;
  std::optional<protocol::Transport> replay_transport;
  std::optional<std::uint16_t> replay_port;

  bool operator==(const Options&) const = default;
};

enum class CommandKind : std::uint8_t { run, help, help_all, version, completion };

struct Command {
  CommandKind kind = CommandKind::run;
  Options options;                // meaningful for run
  std::string completion_script;  // for completion (--completion bash)
};

struct UsageError {
  std::string message;  // one line, names the option: "--time-scale: must be a number > 0"
};

// `arguments` excludes argv[0]. Options take their value as the next argument or after '='
// (parsed with CLI11, base/command_line.hpp); --help and --version win over any problem.
[[nodiscard]] base::Expected<Command, UsageError> parse_command_line(
    std::span<const std::string_view> arguments);

// `option`'s value in the endpoint grammar, on the offering side (base/endpoint.hpp,
// docs/endpoints.md), of the kind `expect`; the error is the line naming the option (an old
// spelling names the new one).
[[nodiscard]] base::Expected<base::Endpoint, UsageError> parse_offered_endpoint(std::string_view option,
                                                                               std::string_view text,
                                                                               base::EndpointExpect expect);

std::string usage_text(std::string_view program_name);
// What --help prints: a screen of usage_text (base::brief_help).
std::string brief_usage_text(std::string_view program_name);
// Where the flash files go unless --flash or a scanner's absolute flash_file says otherwise:
// --flash-dir, else default_flash_folder(), never the scene's folder (a scene in a clone or in
// /usr/share stays untouched).
std::filesystem::path flash_folder(const Options& options);
// The state folder: a unit's StateDirectory= ($STATE_DIRECTORY, the first of its list), else
// $XDG_STATE_HOME/ldoem, else $HOME/.local/state/ldoem (XDG Base Directory; a relative value is
// ignored as the specification says). Empty when none is set. `environment` is getenv.
using Environment = std::function<const char*(const char*)>;
std::filesystem::path default_flash_folder(const Environment& environment = [](const char* name) {
  return static_cast<const char*>(std::getenv(name));
});
// Creates default_flash_folder() (mode 0700, as XDG asks) when the flash goes there; the
// reason when it cannot. A folder given with --flash or --flash-dir must exist already.
std::optional<std::string> make_default_flash_folder(const Options& options);
std::string version_text();

}  // namespace ldoem::daemon
