#include "ldoem/daemon/options.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <set>

#include "ldoem/base/command_line.hpp"
#include "ldoem/base/endpoint.hpp"
#include "ldoem/base/numbers.hpp"

namespace ldoem::daemon {
namespace {

using base::Expected;
using base::Unexpected;

Unexpected<UsageError> usage_error(std::string_view option, std::string_view what) {
  return Unexpected(UsageError{std::string(option) + ": " + std::string(what)});
}

using base::parse_double;
using base::parse_integer;

std::optional<LogLevel> parse_log_level(std::string_view text) {
  for (const LogLevel level : {LogLevel::error, LogLevel::warn, LogLevel::info, LogLevel::debug}) {
    if (text == to_string(level)) {
      return level;
    }
  }
  return std::nullopt;
}

// A host timeout in `unit_seconds` (1e-3: milliseconds), 0 = never, at most 1e6 s.
Expected<std::chrono::milliseconds, UsageError> host_timeout(std::string_view option, std::string_view text,
                                                             double unit_seconds) {
  const auto value = parse_double(text);
  const bool ms = unit_seconds < 1.0;
  if (!value || !(*value >= 0.0 && *value * unit_seconds <= kMaxHostTimeoutSeconds)) {
    return usage_error(option, ms ? "must be a number of milliseconds from 0 (never) to 1e9"
                                  : "must be a number of seconds from 0 (never) to 1e6");
  }
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(*value * unit_seconds * 1000.0)));
}

// What the parser remembers beyond Options, for the checks that involve several options.
struct Seen {
  bool can = false;
  bool no_can = false;
  bool flash = false;
  bool no_flash = false;
};


using ValueHandler = std::function<std::optional<UsageError>(std::string_view value, Options&, Seen&)>;
using FlagHandler = std::function<void(Options&, Seen&)>;

std::optional<UsageError> error_of(const Unexpected<UsageError>& error) { return error.error(); }

const std::map<std::string_view, ValueHandler>& value_options() {
  static const std::map<std::string_view, ValueHandler> handlers{
      {"--scene", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         o.scene_path = std::filesystem::path(std::string(v));
         return std::nullopt;
       }},
      {"--can", [](std::string_view v, Options& o, Seen& s) -> std::optional<UsageError> {
         auto can = parse_offered_endpoint("--can", v, base::EndpointExpect::can);
         if (!can) return can.error();
         const auto& endpoint = std::get<base::CanEndpoint>(*can);
         // One daemon serves one bus: several --can are several id pairs on it.
         if (s.can && o.can_interface && *o.can_interface != endpoint.interface) {
           return UsageError{"--can: every --can names the same interface (one bus), here " + *o.can_interface};
         }
         o.can_interface = endpoint.interface;
         if (endpoint.ids_given) {
           o.can_id_pairs.push_back(CanIdPair{static_cast<std::uint16_t>(endpoint.request_id),
                                              static_cast<std::uint16_t>(endpoint.response_id)});
         }
         s.can = true;
         return std::nullopt;
       }},
      {"--can-ids", [](std::string_view v, Options&, Seen&) -> std::optional<UsageError> {
         return UsageError{"--can-ids " + std::string(v) + " is the old spelling; write --can can:IF:" + std::string(v) +
                           " (docs/endpoints.md)"};
       }},
      {"--tcp", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         auto tcp = parse_offered_endpoint("--tcp", v, base::EndpointExpect::tcp);
         if (!tcp) return tcp.error();
         const auto& endpoint = std::get<base::TcpEndpoint>(*tcp);
         o.tcp = TcpOption{endpoint.host, endpoint.port};
         return std::nullopt;
       }},
      {"--serial", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         auto serial = parse_offered_endpoint("--serial", v, base::EndpointExpect::serial);
         if (!serial) return serial.error();
         o.serial_pty = std::filesystem::path(std::get<base::SerialEndpoint>(*serial).path);
         return std::nullopt;
       }},
      {"--lpt", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         auto lpt = parse_offered_endpoint("--lpt", v, base::EndpointExpect::lpt);
         if (!lpt) return lpt.error();
         const auto& endpoint = std::get<base::LptEndpoint>(*lpt);
         o.lpt = LptOption{endpoint.backend, endpoint.target};
         return std::nullopt;
       }},
      {"--flash", [](std::string_view v, Options& o, Seen& s) -> std::optional<UsageError> {
         o.flash_path = std::filesystem::path(std::string(v));
         s.flash = true;
         return std::nullopt;
       }},
      {"--flash-dir", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         if (v.empty()) return error_of(usage_error("--flash-dir", "expects a folder"));
         o.flash_dir = std::filesystem::path(std::string(v));
         return std::nullopt;
       }},
      {"--time-scale", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto scale = parse_double(v);
         if (!scale || !(*scale >= kMinTimeScale && *scale <= kMaxTimeScale)) {
           return error_of(usage_error("--time-scale", "must be a number from 1e-6 to 1e6"));
         }
         o.time_scale = *scale;
         return std::nullopt;
       }},
      {"--replay", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         o.replay_path = std::filesystem::path(std::string(v));
         return std::nullopt;
       }},
      {"--replay-transport", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         for (const auto kind : {protocol::Transport::tcp, protocol::Transport::serial, protocol::Transport::can}) {
           if (v == protocol::transport_name(kind)) o.replay_transport = kind;
         }
         if (!o.replay_transport) return error_of(usage_error("--replay-transport", "must be tcp, serial or can"));
         return std::nullopt;
       }},
      {"--replay-port", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto port = parse_integer<std::uint16_t>(v);
         if (!port || *port == 0) return error_of(usage_error("--replay-port", "must be a TCP port from 1 to 65535"));
         o.replay_port = *port;
         return std::nullopt;
       }},
      {"--seed", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto seed = parse_integer<std::uint64_t>(v);
         if (!seed) return error_of(usage_error("--seed", "must be an unsigned integer"));
         o.seed = *seed;
         return std::nullopt;
       }},
      {"--log-level", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto level = parse_log_level(v);
         if (!level) return error_of(usage_error("--log-level", "must be error, warn, info or debug"));
         o.log_level = *level;
         return std::nullopt;
       }},
      {"--count-profiles", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto count = parse_integer<std::uint64_t>(v);
         if (!count || *count == 0) return error_of(usage_error("--count-profiles", "must be an integer > 0"));
         o.count_profiles = *count;
         return std::nullopt;
       }},
      {"--timeout", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto seconds = parse_double(v);
         if (!seconds || !(*seconds > 0.0 && *seconds <= kMaxTimeoutSeconds)) {
           return error_of(usage_error("--timeout", "must be a number of seconds > 0 and at most 1e9 (31 years)"));
         }
         o.timeout_s = *seconds;
         return std::nullopt;
       }},
      {"--inter-byte-timeout", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto limit = host_timeout("--inter-byte-timeout", v, 1e-3);
         if (!limit) return limit.error();
         o.host_limits.inter_byte_timeout = *limit;
         return std::nullopt;
       }},
      {"--tcp-silent-timeout", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto limit = host_timeout("--tcp-silent-timeout", v, 1.0);
         if (!limit) return limit.error();
         o.host_limits.silent_timeout = *limit;
         return std::nullopt;
       }},
      {"--tcp-idle-timeout", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto limit = host_timeout("--tcp-idle-timeout", v, 1.0);
         if (!limit) return limit.error();
         o.host_limits.idle_timeout = *limit;
         return std::nullopt;
       }},
      {"--max-clients", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto count = parse_integer<std::size_t>(v);
         if (!count || *count == 0 || *count > kMaxTcpClients) {
           return error_of(usage_error("--max-clients", "must be an integer from 1 to 100000"));
         }
         o.host_limits.max_tcp_clients = *count;
         return std::nullopt;
       }},
      {"--control", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         if (v.empty()) return error_of(usage_error("--control", "expects a socket path"));
         o.control_path = std::filesystem::path(std::string(v));
         return std::nullopt;
       }},
      {"--event-log", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         if (v.empty()) return error_of(usage_error("--event-log", "expects a file path"));
         o.event_log_path = std::filesystem::path(std::string(v));
         return std::nullopt;
       }},
      {"--record", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         if (v.empty()) return error_of(usage_error("--record", "needs a file name"));
         o.record_path = std::filesystem::path(std::string(v));
         return std::nullopt;
       }},
      {"--record-max-mb", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto megabytes = parse_double(v);
         if (!megabytes || !(*megabytes > 0.0 && *megabytes <= kMaxRecordMegabytes)) {
           return error_of(usage_error("--record-max-mb", "must be a number > 0 and at most 1048576 (1 TiB)"));
         }
         o.record_max_bytes = static_cast<std::uint64_t>(*megabytes * 1024 * 1024);
         return std::nullopt;
       }},
      {"--record-files", [](std::string_view v, Options& o, Seen&) -> std::optional<UsageError> {
         const auto files = parse_integer<unsigned>(v);
         if (!files || *files == 0 || *files > kMaxRecordFiles) {
           return error_of(usage_error("--record-files", "must be an integer in [1, 1000]"));
         }
         o.record_files = *files;
         return std::nullopt;
       }},
  };
  return handlers;
}

const std::map<std::string_view, FlagHandler>& flag_options() {
  static const std::map<std::string_view, FlagHandler> handlers{
      {"--no-can", [](Options& o, Seen& s) { o.can_interface.reset(); s.no_can = true; }},
      {"--no-flash", [](Options& o, Seen& s) { o.flash_mode = FlashMode::memory; s.no_flash = true; }},
      {"--virtual-time", [](Options& o, Seen&) { o.virtual_time = true; }},
      {"--realtime", [](Options& o, Seen&) { o.realtime = true; }},
      {"--reset-flash", [](Options& o, Seen&) { o.reset_flash = true; }},
  };
  return handlers;
}

// --replay (docs/replay.md): the recorded device has no scene, flash or noise. --control and
// --event-log serve the monitor (its fault and object commands answer an error). CAN opens only
// when --can names it.
std::optional<UsageError> check_replay(Options& options, const Seen& seen) {
  if (!options.replay_path) {
    if (!options.replay_transport && !options.replay_port) return std::nullopt;
    return UsageError{options.replay_port ? "--replay-port: needs --replay CAPTURE" : "--replay-transport: needs --replay CAPTURE"};
  }
  const char* refused = !options.scene_path.empty() ? "--scene"
                        : seen.flash               ? "--flash"
                        : options.flash_dir        ? "--flash-dir"
                        : options.reset_flash      ? "--reset-flash"
                        : options.seed             ? "--seed"
                                                   : nullptr;
  if (refused != nullptr) {
    return UsageError{std::string(refused) + ": conflicts with --replay (a recorded device has no scene, flash, " +
                      "noise or faults)"};
  }
  options.flash_mode = FlashMode::memory;
  if (!seen.can) options.can_interface.reset();
  if (options.can_interface || options.tcp || options.serial_pty) return std::nullopt;
  return UsageError{"--replay: no endpoint: give --tcp tcp:HOST[:PORT], --serial serial:pty:PATH or --can can:IF"};
}

std::optional<UsageError> check_combination(Options& options, const Seen& seen) {
  if (auto error = check_replay(options, seen)) return error;
  if (options.scene_path.empty() && !options.replay_path) {
    return UsageError{"--scene: required (try --help)"};
  }
  if (seen.can && seen.no_can) {
    return UsageError{"--no-can: conflicts with --can"};
  }
  if (seen.flash && seen.no_flash) {
    return UsageError{"--no-flash: conflicts with --flash"};
  }
  if (options.flash_dir && (seen.flash || seen.no_flash)) {
    return UsageError{seen.flash ? "--flash-dir: conflicts with --flash" : "--flash-dir: conflicts with --no-flash"};
  }
  if (options.realtime && options.virtual_time) {
    // Virtual time computes flat out: at a real-time priority it would take a core from the machine.
    return UsageError{"--realtime: conflicts with --virtual-time"};
  }
  if (options.reset_flash && seen.no_flash) {
    return UsageError{"--reset-flash: conflicts with --no-flash"};
  }
  std::set<std::uint16_t> request_ids;
  std::set<std::uint16_t> response_ids;
  for (const CanIdPair& pair : options.can_id_pairs) {
    if (!request_ids.insert(pair.request_id).second || !response_ids.insert(pair.response_id).second ||
        request_ids.count(pair.response_id) != 0 || response_ids.count(pair.request_id) != 0) {
      return UsageError{"--can: every identifier may be used by one pair only"};
    }
  }
  // "No host transport left" needs the scene (its scanners may name endpoints): scanner_options.hpp.
  if (options.flash_mode == FlashMode::file && !seen.flash) {
    if (flash_folder(options).empty()) {
      return UsageError{"--flash: no folder for it (HOME, XDG_STATE_HOME and STATE_DIRECTORY unset): give --flash, "
                        "--flash-dir or --no-flash"};
    }
    options.flash_path = flash_folder(options) / options.scene_path.filename();
    options.flash_path += std::string(kFlashFileSuffix);
  }
  if (options.flash_mode == FlashMode::memory) {
    options.flash_path.clear();
  }
  return std::nullopt;
}

}  // namespace

std::filesystem::path flash_folder(const Options& options) {
  return options.flash_dir ? *options.flash_dir : default_flash_folder();
}

std::filesystem::path default_flash_folder(const Environment& environment) {
  if (const char* state = environment("STATE_DIRECTORY"); state != nullptr && state[0] == '/') {
    const std::string_view list(state);
    return std::filesystem::path(std::string(list.substr(0, list.find(':'))));
  }
  if (const char* xdg = environment("XDG_STATE_HOME"); xdg != nullptr && xdg[0] == '/') {
    return std::filesystem::path(xdg) / "ldoem";
  }
  if (const char* home = environment("HOME"); home != nullptr && home[0] == '/') {
    return std::filesystem::path(home) / ".local" / "state" / "ldoem";
  }
  return {};
}

std::optional<std::string> make_default_flash_folder(const Options& options) {
  const std::filesystem::path folder = default_flash_folder();
  if (options.flash_mode != FlashMode::file || options.flash_dir || folder.empty() ||
      options.flash_path.parent_path() != folder) {
    return std::nullopt;
  }
  std::filesystem::path partial;
  for (const std::filesystem::path& part : folder) {
    partial /= part;
    if (::mkdir(partial.c_str(), 0700) != 0 && errno != EEXIST) {
      return "flash folder " + partial.string() + ": " + std::strerror(errno);
    }
  }
  return std::nullopt;
}

Expected<base::Endpoint, UsageError> parse_offered_endpoint(std::string_view option, std::string_view text,
                                                            base::EndpointExpect expect) {
  auto endpoint = base::parse_endpoint(text, base::EndpointUse{base::EndpointSide::offer, expect});
  if (!endpoint) {
    return Unexpected(UsageError{base::describe_for_option(option, endpoint.error())});
  }
  return std::move(endpoint).value();
}

Expected<Command, UsageError> parse_command_line(std::span<const std::string_view> arguments) {
  Command command;
  Seen seen;
  base::CommandLine command_line("ldoem-emud", base::HelpPrecedence::before_problems);
  CLI::App& app = command_line.app();
  for (const auto& [name, handler] : flag_options()) {
    app.add_flag_callback(std::string(name), [&, &handler = handler] { handler(command.options, seen); })
        ->disable_flag_override();
  }
  for (const auto& [name, handler] : value_options()) {
    // Every value is applied in turn: --can adds an id pair each time, the others keep the last.
    app.add_option_function<std::vector<std::string>>(
           std::string(name),
           [&, &handler = handler](const std::vector<std::string>& values) {
             for (const std::string& value : values) {
               if (auto error = handler(value, command.options, seen)) throw CLI::ValidationError(error->message);
             }
           })
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->allow_extra_args(false);  // one value per occurrence
  }
  if (auto problem = command_line.parse(arguments)) {
    return Unexpected(UsageError{std::move(*problem)});
  }
  if (command_line.help_requested()) {
    return Command{CommandKind::help, {}, {}};
  }
  if (command_line.help_all_requested()) {
    return Command{CommandKind::help_all, {}, {}};
  }
  if (command_line.version_requested()) {
    return Command{CommandKind::version, {}, {}};
  }
  if (command_line.completion_requested()) {
    return Command{CommandKind::completion, {}, command_line.completion_script()};
  }
  if (auto error = check_combination(command.options, seen)) {
    return Unexpected(std::move(*error));
  }
  return command;
}

std::string version_text() { return base::version_line("ldoem-emud"); }

std::string usage_text(std::string_view program_name) {
  const std::string p(program_name);
  return "Usage: " + p + " --scene FILE [OPTIONS]\n"
         "       " + p + " --replay CAPTURE [OPTIONS]\n"
         "Emulates a SICK LD-OEM laser scanner at the byte level: host protocol on CAN (ISO-TP, D1),\n"
         "TCP (spec 4.1) and a serial pty (spec 4.2); the tilt stepper's pseudo-LPT on a pty or gpio (D8).\n"
         "\n"
         "Options (default in brackets):\n"
         "  --scene FILE          YAML scene to emulate (required)\n"
         "  --can can:IF[:REQ:RESP]  SocketCAN interface for the host protocol; REQ:RESP are the\n"
         "                        host->LD and LD->host 11-bit ids in hex; repeat with other ids for\n"
         "                        more hosts, each pair its own connection [can:vcan0, ids from flash:\n"
         "                        6C0:6C1]\n"
         "  --no-can              no CAN transport (then --tcp or --serial is needed)\n"
         "  --tcp tcp:HOST[:PORT]  TCP server on HOST, port 49152 if omitted, 0 = any free port [off]\n"
         "  --serial serial:pty:PATH  serial line on a pty, symlinked at PATH [off]\n"
         "  --lpt lpt:pty:PATH    tilt stepper register on a pty, symlinked at PATH [off]\n"
         "  --lpt lpt:gpio:CHIP   tilt stepper on lines DIR, CLK, MODE of a gpio chip [off]\n"
         "                        (endpoints: docs/endpoints.md; the host tools take the same text)\n"
         "  --flash FILE          flash image file [STATE/<scene>.flash, STATE: $STATE_DIRECTORY,\n"
         "                        else $XDG_STATE_HOME/ldoem, else ~/.local/state/ldoem]\n"
         "  --flash-dir DIR       flash files in DIR instead of STATE, same names (<scene>.flash;\n"
         "                        several scanners: <scene>.<name>.flash or flash_file) [STATE]\n"
         "  --no-flash            keep the flash in memory only\n"
         "  --reset-flash         start from the scene's flash defaults even when FILE cannot be\n"
         "                        read or parsed, and replace it (without: exit 2) [off]\n"
         "  --time-scale X        simulated seconds per wall second, 1e-6..1e6 [1]\n"
         "  --virtual-time        run the simulated clock as fast as possible: when nothing is\n"
         "                        ready, jump to the next deadline (tests, benchmarks) [off]\n"
         "  --realtime            SCHED_FIFO priority 10 and locked memory when permitted, so a\n"
         "                        busy machine delays revolutions less; says so when not [off]\n"
         "  --seed N              noise seed, overrides the scene's [scene's seed]\n"
         "  --inter-byte-timeout MS  drop a TCP frame or serial package the host left incomplete\n"
         "                        this long (spec 6), 0 = never [500]\n"
         "  --tcp-silent-timeout S  close a TCP connection without a complete telegram S seconds\n"
         "                        after connecting, 0 = never [60]\n"
         "  --tcp-idle-timeout S  close a TCP connection that sent nothing for S seconds,\n"
         "                        0 = never [0]\n"
         "  --max-clients N       TCP connections served at once, per scanner (1..100000); a\n"
         "                        further one is accepted and closed at once [64]\n"
         "  --log-level LEVEL     error|warn|info|debug; info logs every telegram [warn]\n"
         "  --count-profiles N    stop (exit 0) after N profile telegrams in total [no limit]\n"
         "  --timeout SECONDS     stop (exit 0) after this many wall seconds, at most 1e9 [no limit]\n"
         "  --record FILE         write every telegram on every transport, with device time, to\n"
         "                        FILE (pcapng for Wireshark/tshark, docs/capture.md) [off]\n"
         "  --record-max-mb N     rotate FILE at N MiB (at most 1048576): FILE.1, FILE.2, ... [no cap]\n"
         "  --record-files K      files kept when rotating, FILE included (at most 1000) [10]\n"
         "  --control PATH        control socket (JSON lines, QMP-shaped, mode 0600) for\n"
         "                        faults and status; docs/faults.md, ldoem-ctl [off]\n"
         "  --event-log FILE      write the fault and state events, one JSON line each [off]\n"
         "  --replay CAPTURE      serve the device recorded in CAPTURE (pcapng, pcap, candump -l)\n"
         "                        instead of a scene: CAN only with --can; --scene, --flash\n"
         "                        and --seed are errors then (docs/replay.md) [off]\n"
         "  --replay-transport T  replay its tcp, serial or can telegrams [the most]\n"
         "  --replay-port N       the device's TCP port in CAPTURE [detected]\n"
         "  --help, -h            the most used options\n"
         "  --help-all            this text\n"
         "  --version             print the name and version\n"
         "  --completion bash     print a bash completion\n"
         "\n"
         "On start the daemon prints one line per endpoint on stdout (\"tcp 127.0.0.1:49152\",\n"
         "\"serial /dev/pts/4\", \"lpt /dev/pts/5\", \"can vcan0 6C0:6C1\"), then \"ready\".\n"
         "A scene with a scanners: list runs several scanners in one daemon: each one's TCP port,\n"
         "CAN ids, serial, LPT and flash file come from the scene, --tcp, --can with ids, --serial,\n"
         "--lpt, --flash and --record are errors then (--flash-dir is not), and \"scanner NAME\"\n"
         "comes before each scanner's endpoint lines (docs/scenes.md \"Several scanners\").\n"
         "SIGUSR1 writes the counters (framing errors, ISO-TP drops, skipped profiles) to stderr.\n"
         "\n"
         "Exit status:\n"
         "  0        stopped by --count-profiles or --timeout\n"
         "  1        runtime failure (event loop, socket error)\n"
         "  2        usage or configuration error: bad option, bad scene (file:line:col),\n"
         "           CAN interface missing or down, pty/port cannot be opened\n"
         "  128+N    stopped by signal N (130 SIGINT, 143 SIGTERM); flash saved first\n"
         "\n"
         "Examples:\n"
         "  " + p + " --scene scenes/corridor.yaml --can can:vcan0 --lpt lpt:pty:/tmp/ldoem-lpt\n"
         "  " + p + " --scene scenes/minimal.yaml --no-can --tcp tcp:127.0.0.1:49152 --log-level info\n"
         "  " + p + " --scene scenes/minimal.yaml --no-can --serial serial:pty:/tmp/ldoem-serial --no-flash\n"
         "  " + p + " --scene scenes/minimal.yaml --can can:vcan0:6C0:6C1 --can can:vcan0:6C2:6C3\n"
         "  " + p + " --scene scenes/faults/motor-stall-mid-stream.yaml --no-can --tcp tcp:127.0.0.1:49152 --control /tmp/ldoem.ctl\n"
         "  " + p + " --replay scan.pcapng --tcp tcp:127.0.0.1:49152 --lpt lpt:pty:/tmp/ldoem-lpt\n";
}

std::string brief_usage_text(std::string_view program_name) {
  return base::brief_help(program_name, usage_text(program_name),
                          "Emulate a SICK LD-OEM laser scanner at the byte level (CAN, TCP, serial, LPT).",
                          {"--scene", "--can", "--no-can", "--tcp", "--serial", "--lpt", "--flash", "--no-flash",
                           "--time-scale", "--log-level", "--record", "--control", "--replay", "--help", "--version"});
}

}  // namespace ldoem::daemon
