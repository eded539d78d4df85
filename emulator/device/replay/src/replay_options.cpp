#include "ldoem/replay/replay_options.hpp"

#include "ldoem/base/command_line.hpp"
#include "ldoem/base/numbers.hpp"

namespace ldoem::replay {
namespace {

// A number of seconds or a speed factor: finite and above 0.
std::optional<double> parse_positive(std::string_view text) {
  const auto value = base::parse_double(text);
  if (!value || *value <= 0) return std::nullopt;
  return value;
}

// What one option does with one value; nothing when it is taken, else the reason ("--speed:
// ..."). Runs once per occurrence, in command-line order.
struct Reader {
  ReplayOptions& options;
  bool any_endpoint = false;

  std::optional<std::string> apply(std::string_view name, const std::string& text) {
    // The endpoints in the grammar of ldoem-emud (docs/endpoints.md): replay offers them too.
    if (name == "--tcp") {
      auto tcp = daemon::parse_offered_endpoint(name, text, base::EndpointExpect::tcp);
      if (!tcp) return tcp.error().message;
      const auto& endpoint = std::get<base::TcpEndpoint>(*tcp);
      options.endpoints.tcp = daemon::TcpOption{endpoint.host, endpoint.port};
      any_endpoint = true;
    } else if (name == "--serial") {
      auto serial = daemon::parse_offered_endpoint(name, text, base::EndpointExpect::serial);
      if (!serial) return serial.error().message;
      options.endpoints.serial_pty = std::get<base::SerialEndpoint>(*serial).path;
      any_endpoint = true;
    } else if (name == "--can") {
      auto can = daemon::parse_offered_endpoint(name, text, base::EndpointExpect::can);
      if (!can) return can.error().message;
      const auto& endpoint = std::get<base::CanEndpoint>(*can);
      options.endpoints.can_interface = endpoint.interface;
      if (endpoint.ids_given) {
        options.endpoints.can_id_pairs.push_back(daemon::CanIdPair{static_cast<std::uint16_t>(endpoint.request_id),
                                                                   static_cast<std::uint16_t>(endpoint.response_id)});
      }
      any_endpoint = true;
    } else if (name == "--can-ids") {
      return "--can-ids " + text + " is the old spelling; write --can can:IF:" + text + " (docs/endpoints.md)";
    } else if (name == "--lpt") {
      auto lpt = daemon::parse_offered_endpoint(name, text, base::EndpointExpect::lpt);
      if (!lpt) return lpt.error().message;
      const auto& endpoint = std::get<base::LptEndpoint>(*lpt);
      options.endpoints.lpt = daemon::LptOption{
          endpoint.backend == base::LptBackend::gpio ? daemon::LptBackend::gpio : daemon::LptBackend::pty, endpoint.target};
    } else if (name == "--speed") {
      const auto speed = parse_positive(text);
      // The daemon's --time-scale range: recorded delay / speed stays a representable int64 ns.
      if (!speed || !(*speed >= daemon::kMinTimeScale && *speed <= daemon::kMaxTimeScale)) {
        return "--speed: must be a number from 1e-6 to 1e6, got `" + text + "`";
      }
      options.speed = *speed;
    } else if (name == "--transport") {
      if (text == "tcp") options.transport = protocol::Transport::tcp;
      else if (text == "serial") options.transport = protocol::Transport::serial;
      else if (text == "can") options.transport = protocol::Transport::can;
      else return "--transport: must be tcp, serial or can, got `" + text + "`";
    } else if (name == "--port") {
      const auto port = base::parse_integer<std::uint16_t>(text);
      if (!port || *port == 0) return "--port: must be a TCP port from 1 to 65535, got `" + text + "`";
      options.capture_tcp_port = *port;
    } else if (name == "--timeout") {
      const auto seconds = parse_positive(text);
      if (!seconds || *seconds > daemon::kMaxTimeoutSeconds) {
        return "--timeout: must be seconds > 0 and at most 1e9, got `" + text + "`";
      }
      options.endpoints.timeout_s = *seconds;
    } else if (name == "--log-level") {
      if (text == "error") options.endpoints.log_level = daemon::LogLevel::error;
      else if (text == "warn") options.endpoints.log_level = daemon::LogLevel::warn;
      else if (text == "info") options.endpoints.log_level = daemon::LogLevel::info;
      else if (text == "debug") options.endpoints.log_level = daemon::LogLevel::debug;
      else return "--log-level: must be error, warn, info or debug, got `" + text + "`";
    }
    return std::nullopt;
  }
};

constexpr std::string_view kValueOptions[] = {"--tcp",   "--serial",    "--can",     "--can-ids",  "--lpt",
                                             "--speed", "--transport", "--port", "--timeout", "--log-level"};

base::Unexpected<ReplayUsageError> usage(std::string message) {
  return base::Unexpected(ReplayUsageError{std::move(message)});
}

}  // namespace

base::Expected<ReplayOptions, ReplayUsageError> parse_replay_options(std::span<const std::string_view> arguments) {
  ReplayOptions options;
  options.endpoints.can_interface.reset();  // CAN only when asked for
  options.endpoints.flash_mode = daemon::FlashMode::memory;
  Reader reader{options};
  base::CommandLine command_line("ldoem-replay");
  CLI::App& app = command_line.app();
  for (const std::string_view option : kValueOptions) {
    // Every value is applied in turn: --can adds an id pair each time, the others keep the last.
    const std::string name(option);
    app.add_option_function<std::vector<std::string>>(name, [&reader, name](const std::vector<std::string>& values) {
         for (const std::string& value : values) {
           if (auto problem = reader.apply(name, value)) throw CLI::ValidationError(*problem);
         }
       })
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->allow_extra_args(false);  // one value per occurrence
  }
  std::vector<std::string> captures;
  app.add_option("CAPTURE", captures)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  if (auto problem = command_line.parse(arguments)) return usage(*problem);
  if (command_line.completion_requested()) {
    options.completion_script = command_line.completion_script();
    return options;
  }
  options.help = command_line.help_requested();
  options.help_all = command_line.help_all_requested();
  options.version = command_line.version_requested();
  if (options.help || options.help_all || options.version) return options;
  if (captures.size() > 1) return usage("more than one CAPTURE given: `" + captures[1] + "`");
  if (captures.empty()) return usage("no CAPTURE given (try --help)");
  options.capture = captures.front();
  if (!reader.any_endpoint) {
    return usage("no endpoint: give --tcp tcp:HOST[:PORT], --serial serial:pty:PATH or --can can:IF");
  }
  return options;
}

daemon::Options daemon_options(const ReplayOptions& options) {
  daemon::Options served = options.endpoints;
  served.replay_path = options.capture;
  served.replay_transport = options.transport;
  served.replay_port = options.capture_tcp_port;
  served.time_scale = options.speed;
  return served;
}

std::string replay_usage_text() {
  return "Usage: ldoem-replay CAPTURE (--tcp tcp:HOST[:PORT] | --serial serial:pty:PATH | --can can:IF)... [OPTIONS]\n"
         "Acts as the LD-OEM recorded in CAPTURE (docs/replay.md): each request is answered with the\n"
         "recorded replies to the same request, profiles at their recorded delays. CAPTURE: a pcapng\n"
         "from ldoem-emud --record or ldoem-conformance --record, a pcap of the device's TCP port\n"
         "(tcpdump, Wireshark; any port), or a can-utils `candump -l` log of the D1 identifiers.\n"
         "The same as ldoem-emud --replay CAPTURE, --speed being its --time-scale.\n"
         "\n"
         "Endpoints (the daemon's, docs/endpoints.md; at least one):\n"
         "  --tcp tcp:HOST[:PORT]  TCP server; port 49152 if omitted, 0 = any free port\n"
         "  --serial serial:pty:PATH  serial line on a pty, symlinked at PATH\n"
         "  --can can:IF[:REQ:RESP]  ISO-TP on SocketCAN interface IF, hex 11-bit ids (D1) [6C0:6C1]\n"
         "  --lpt lpt:pty:PATH|lpt:gpio:CHIP  accept the tilt stepper's writes (counted, not replayed)\n"
         "Options (default in brackets):\n"
         "  --speed X             recorded seconds per replayed second, 1e-6..1e6 [1]\n"
         "  --transport T         replay the recorded tcp, serial or can telegrams [the most]\n"
         "  --port N              the device's TCP port in CAPTURE [the port of the STX \"USP\" frames]\n"
         "  --timeout S           stop (exit 0) after S wall seconds, at most 1e9 [none]\n"
         "  --log-level L         error|warn|info|debug; info logs every request and answer [warn]\n"
         "  --help, -h            the most used options\n"
         "  --help-all            this text\n"
         "  --version             print the name and version\n"
         "  --completion bash     print a bash completion\n"
         "\n"
         "An unexpected request (not in the recording) is logged with a diagnostic on stderr and\n"
         "answered SERVICE_FAILURE (D2): the reason decode_request gives, or 3 for a valid request.\n"
         "On start one line per endpoint is printed on stdout, then `ready`.\n"
         "Exit status: 0 after --timeout, 1 runtime failure, 2 usage error or unreadable capture,\n"
         "128 + N after signal N.\n"
         "\n"
         "Examples:\n"
         "  ldoem-replay scan.pcapng --tcp tcp:127.0.0.1:49152 --lpt lpt:pty:/tmp/ldoem-lpt\n"
         "  ldoem-replay candump-2026-11-25.log --can can:vcan0 --speed 2\n";
}

std::string replay_brief_usage_text() {
  return base::brief_help("ldoem-replay", replay_usage_text(), "Serve a recorded LD-OEM conversation as a device (docs/replay.md).",
                          {"--tcp", "--serial", "--can", "--lpt", "--speed", "--transport", "--timeout", "--log-level",
                           "--help", "--version"});
}

}  // namespace ldoem::replay
