#include "ldoem/replay/replay_options.hpp"

#include <charconv>
#include <cmath>

namespace ldoem::replay {
namespace {

base::Unexpected<ReplayUsageError> usage(std::string message) {
  return base::Unexpected(ReplayUsageError{std::move(message)});
}

std::optional<double> parse_positive(std::string_view text) {
  double value = 0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  if (result.ec != std::errc{} || result.ptr != text.data() + text.size() || !std::isfinite(value) || value <= 0) {
    return std::nullopt;
  }
  return value;
}

}  // namespace

base::Expected<ReplayOptions, ReplayUsageError> parse_replay_options(std::span<const std::string_view> arguments) {
  ReplayOptions options;
  options.endpoints.can_interface.reset();  // CAN only when asked for
  options.endpoints.flash_mode = daemon::FlashMode::memory;
  bool any_endpoint = false;
  for (std::size_t i = 0; i < arguments.size(); ++i) {
    std::string_view argument = arguments[i];
    if (argument == "--help" || argument == "-h") {
      options.help = true;
      continue;
    }
    if (!argument.starts_with("-")) {
      if (!options.capture.empty()) return usage("more than one CAPTURE given: `" + std::string(argument) + "`");
      options.capture = std::string(argument);
      continue;
    }
    std::string_view name = argument;
    std::optional<std::string_view> value;
    if (const std::size_t equals = argument.find('='); equals != std::string_view::npos) {
      name = argument.substr(0, equals);
      value = argument.substr(equals + 1);
    }
    if (!value) {
      if (i + 1 >= arguments.size()) return usage(std::string(name) + ": needs a value");
      value = arguments[++i];
    }
    const std::string text(*value);
    if (name == "--tcp") {
      auto tcp = daemon::parse_tcp_option(text);
      if (!tcp) return usage(tcp.error().message);
      options.endpoints.tcp = *tcp;
      any_endpoint = true;
    } else if (name == "--serial") {
      if (!text.starts_with("pty:") || text.size() == 4) return usage("--serial: expected pty:PATH, got `" + text + "`");
      options.endpoints.serial_pty = text.substr(4);
      any_endpoint = true;
    } else if (name == "--can") {
      if (text.empty()) return usage("--can: empty interface name");
      options.endpoints.can_interface = text;
      any_endpoint = true;
    } else if (name == "--can-ids") {
      auto pair = daemon::parse_can_id_pair(text);
      if (!pair) return usage(pair.error().message);
      options.endpoints.can_id_pairs.push_back(*pair);
    } else if (name == "--lpt") {
      if (text.starts_with("pty:") && text.size() > 4) {
        options.endpoints.lpt = daemon::LptOption{daemon::LptBackend::pty, text.substr(4)};
      } else if (text.starts_with("gpio:") && text.size() > 5) {
        options.endpoints.lpt = daemon::LptOption{daemon::LptBackend::gpio, text.substr(5)};
      } else {
        return usage("--lpt: expected pty:PATH or gpio:CHIP, got `" + text + "`");
      }
    } else if (name == "--speed") {
      const auto speed = parse_positive(text);
      // The daemon's --time-scale range: recorded delay / speed stays a representable int64 ns.
      if (!speed || !(*speed >= daemon::kMinTimeScale && *speed <= daemon::kMaxTimeScale)) {
        return usage("--speed: must be a number from 1e-6 to 1e6, got `" + text + "`");
      }
      options.speed = *speed;
    } else if (name == "--transport") {
      if (text == "tcp") options.transport = protocol::WireTransport::tcp;
      else if (text == "serial") options.transport = protocol::WireTransport::serial;
      else if (text == "can") options.transport = protocol::WireTransport::can;
      else return usage("--transport: must be tcp, serial or can, got `" + text + "`");
    } else if (name == "--timeout") {
      const auto seconds = parse_positive(text);
      if (!seconds || *seconds > daemon::kMaxTimeoutSeconds) {
        return usage("--timeout: must be seconds > 0 and at most 1e9, got `" + text + "`");
      }
      options.endpoints.timeout_s = *seconds;
    } else if (name == "--log-level") {
      if (text == "error") options.endpoints.log_level = daemon::LogLevel::error;
      else if (text == "warn") options.endpoints.log_level = daemon::LogLevel::warn;
      else if (text == "info") options.endpoints.log_level = daemon::LogLevel::info;
      else if (text == "debug") options.endpoints.log_level = daemon::LogLevel::debug;
      else return usage("--log-level: must be error, warn, info or debug, got `" + text + "`");
    } else {
      return usage("unknown option `" + std::string(name) + "` (try --help)");
    }
  }
  if (options.help) return options;
  if (options.capture.empty()) return usage("no CAPTURE given (try --help)");
  if (!any_endpoint) return usage("no endpoint: give --tcp HOST[:PORT], --serial pty:PATH or --can IF");
  if (!options.endpoints.can_id_pairs.empty() && !options.endpoints.can_interface) return usage("--can-ids: only with --can");
  return options;
}

std::string replay_usage_text() {
  return "Usage: ldoem-replay CAPTURE (--tcp HOST[:PORT] | --serial pty:PATH | --can IF)... [OPTIONS]\n"
         "Acts as the LD-OEM recorded in CAPTURE (docs/replay.md): each request is answered with the\n"
         "recorded replies to the same request, profiles at their recorded delays. CAPTURE: a pcapng\n"
         "from ldoem-emud --record or ldoem-conformance --record, a pcap of TCP port 49152 (tcpdump,\n"
         "Wireshark), or a can-utils `candump -l` log of the D1 identifiers.\n"
         "\n"
         "Endpoints (the daemon's syntax, docs/emulator.md; at least one):\n"
         "  --tcp HOST[:PORT]     TCP server; port 49152 if omitted, 0 = any free port\n"
         "  --serial pty:PATH     serial line on a pty, symlinked at PATH\n"
         "  --can IF              ISO-TP on SocketCAN interface IF (D1)\n"
         "  --can-ids REQ:RESP    hex 11-bit identifiers [6C0:6C1]\n"
         "  --lpt pty:PATH|gpio:CHIP  accept the tilt stepper's writes (counted, not replayed)\n"
         "Options (default in brackets):\n"
         "  --speed X             recorded seconds per replayed second, 1e-6..1e6 [1]\n"
         "  --transport T         replay the recorded tcp, serial or can telegrams [the most]\n"
         "  --timeout S           stop (exit 0) after S wall seconds, at most 1e9 [none]\n"
         "  --log-level L         error|warn|info|debug; info logs every request and answer [warn]\n"
         "  --help, -h            this text\n"
         "\n"
         "An unexpected request (not in the recording) is logged with a diagnostic on stderr and\n"
         "answered SERVICE_FAILURE (D2): the reason decode_request gives, or 3 for a valid request.\n"
         "On start one line per endpoint is printed on stdout, then `ready`.\n"
         "Exit status: 0 after --timeout, 1 runtime failure, 2 usage error or unreadable capture,\n"
         "128 + N after signal N.\n"
         "\n"
         "Examples:\n"
         "  ldoem-replay scan.pcapng --tcp 127.0.0.1:49152 --lpt pty:/tmp/ldoem-lpt\n"
         "  ldoem-replay candump-2026-11-25.log --can vcan0 --speed 2\n";
}

}  // namespace ldoem::replay
