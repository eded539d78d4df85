#include "options.hpp"

#include <cmath>
#include <fnmatch.h>

#include "ldoem/base/command_line.hpp"
#include "ldoem/base/endpoint.hpp"
#include "ldoem/base/numbers.hpp"

namespace ldoem::conformance {
namespace {

using base::Expected;
using base::Unexpected;

Unexpected<SuiteUsageError> usage(std::string message) { return Unexpected<SuiteUsageError>(SuiteUsageError{std::move(message)}); }

using base::parse_double;

struct Parser {
  SuiteOptions options;
  int endpoint_options = 0;

  // --can, --tcp and --serial take the endpoint grammar of every tool (docs/endpoints.md).
  Expected<std::monostate, SuiteUsageError> take_endpoint(std::string_view name, std::string_view value,
                                                     base::EndpointExpect expect) {
    ++endpoint_options;
    auto endpoint = base::parse_endpoint(value, base::EndpointUse{base::EndpointSide::connect, expect});
    if (!endpoint) return usage(base::describe_for_option(name, endpoint.error()));
    options.endpoint = *endpoint;
    return std::monostate{};
  }

  Expected<std::monostate, SuiteUsageError> apply(std::string_view name, std::string_view value) {
    if (name == "--can") {
      return take_endpoint(name, value, base::EndpointExpect::can);
    } else if (name == "--ids") {
      std::string ids(value);
      for (char& c : ids) c = c == ',' ? ':' : c;
      return usage("--ids " + std::string(value) + " is the old spelling; write --can can:IF:" + ids +
                   " (docs/endpoints.md)");
    } else if (name == "--tcp") {
      return take_endpoint(name, value, base::EndpointExpect::tcp);
    } else if (name == "--serial") {
      return take_endpoint(name, value, base::EndpointExpect::serial);
    } else if (name == "--target") {
      if (value == "emulator") {
        options.target = Target::emulator;
      } else if (value == "device") {
        options.target = Target::device;
      } else {
        return usage("--target: must be `emulator` or `device`, got `" + std::string(value) + "`");
      }
    } else if (name == "--time-scale") {
      const auto scale = parse_double(value);
      // Bounded so that wall = simulated / X stays a finite, representable number of ms.
      if (!scale || !(*scale >= 1e-3 && *scale <= 1e6)) {
        return usage("--time-scale: must be a number in [0.001, 1000000], got `" + std::string(value) + "`");
      }
      options.time_scale = *scale;
    } else if (name == "--timeout") {
      const auto seconds = parse_double(value);
      // At most a week: seconds * 1000 must fit the integer it is converted to.
      if (!seconds || !(*seconds > 0 && *seconds <= 604800)) {
        return usage("--timeout: must be seconds in (0, 604800], got `" + std::string(value) + "`");
      }
      options.reply_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(*seconds * 1000)));
    } else if (name == "--filter") {
      if (value.empty()) return usage("--filter: empty pattern");
      options.filters.emplace_back(value);
    } else if (name == "--exclude") {
      if (value.empty()) return usage("--exclude: empty pattern");
      options.excludes.emplace_back(value);
    } else if (name == "--vectors") {
      options.vectors_file = std::string(value);
    } else if (name == "--against") {
      options.against = std::string(value);
    } else if (name == "--port") {
      const auto port = base::parse_integer<std::uint16_t>(value);
      if (!port || *port == 0) return usage("--port: must be a TCP port from 1 to 65535, got `" + std::string(value) + "`");
      options.against_tcp_port = *port;
    } else if (name == "--mask") {
      if (value.empty()) return usage("--mask: empty pattern");
      options.masks.emplace_back(value);
    } else if (name == "--record") {
      if (value.empty()) return usage("--record: empty file name");
      options.record = std::string(value);
    } else {
      return usage("unknown option `" + std::string(name) + "` (try --help)");
    }
    return std::monostate{};
  }

  Expected<std::monostate, SuiteUsageError> finish() {
    if (endpoint_options > 1) return usage("give only one of --can, --tcp, --serial");
    if (!options.endpoint && !options.list && !options.help && !options.help_all) {
      return usage("no endpoint: give --can can:IF, --tcp tcp:HOST[:PORT] or --serial serial:TTY (try --help)");
    }
    return std::monostate{};
  }
};

constexpr std::string_view kValueOptions[] = {"--can",     "--ids",    "--tcp",     "--serial", "--target", "--time-scale",
                                             "--timeout", "--filter", "--exclude", "--vectors", "--against", "--mask",
                                             "--record",    "--port"};

}  // namespace

Expected<SuiteOptions, SuiteUsageError> parse_options(std::span<const std::string_view> arguments) {
  Parser parser;
  base::CommandLine command_line("ldoem-conformance");
  CLI::App& app = command_line.app();
  app.add_flag("--list", parser.options.list);
  app.add_flag("--virtual-time", parser.options.virtual_time);
  app.add_flag("--strict-timing", parser.options.strict_timing);
  app.add_flag("-v,--verbose", parser.options.verbose);
  for (const std::string_view option : kValueOptions) {
    // Every value is applied, repeats included: --filter and --mask add patterns, a second
    // endpoint option is the error "give only one".
    const std::string name(option);
    app.add_option_function<std::vector<std::string>>(name, [&parser, name](const std::vector<std::string>& values) {
         for (const std::string& value : values) {
           if (auto applied = parser.apply(name, value); !applied) throw CLI::ValidationError(applied.error().message);
         }
       })
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->allow_extra_args(false);  // one value per occurrence
  }
  // After the value options: CLI11 applies them in declaration order, so --mask comes first.
  for (const auto& [flag, globs] : {std::pair{"--mask-times", &kTimeFieldMasks}, {"--mask-counters", &kCounterFieldMasks}}) {
    app.add_flag_callback(flag, [&parser, globs = globs] {
      parser.options.masks.insert(parser.options.masks.end(), globs->begin(), globs->end());
    });
  }
  if (auto problem = command_line.parse(arguments)) return usage(*problem);
  parser.options.help = command_line.help_requested();
  parser.options.help_all = command_line.help_all_requested();
  parser.options.version = command_line.version_requested();
  if (parser.options.version) return parser.options;
  if (command_line.completion_requested()) parser.options.completion_script = command_line.completion_script();
  if (parser.options.completion_script) return parser.options;
  if (!parser.options.masks.empty() && !parser.options.against) {
    return usage("--mask, --mask-times and --mask-counters need --against");
  }
  if (parser.options.against_tcp_port && !parser.options.against) return usage("--port: only with --against");
  auto finished = parser.finish();
  if (!finished) return Unexpected<SuiteUsageError>(finished.error());
  return parser.options;
}

std::string transport_prefix(const driver::Endpoint& endpoint) {
  if (std::holds_alternative<driver::CanEndpoint>(endpoint)) return "can";
  if (std::holds_alternative<driver::SerialEndpoint>(endpoint)) return "serial";
  return "tcp";
}

bool matches_any(const std::vector<std::string>& filters, std::string_view name) {
  if (filters.empty()) return true;
  const std::string text(name);
  for (const std::string& filter : filters) {
    if (fnmatch(filter.c_str(), text.c_str(), 0) == 0) return true;
  }
  return false;
}

std::string usage_text(std::string_view program_name) {
  const std::string p(program_name);
  return "Usage: " + p + " (--can can:IF[:REQ:RESP] | --tcp tcp:HOST[:PORT] | --serial serial:TTY) [OPTIONS]\n"
         "Host-protocol conformance suite for a SICK LD-OEM (docs/conformance.md): sends the golden\n"
         "vectors of spec section 7, the S1/S2 conversations, every D2 failure, every illegal state\n"
         "transition, spin-up and profile-cadence timing, and checks the replies byte by byte.\n"
         "\n"
         "Endpoint (exactly one; docs/endpoints.md):\n"
         "  --can can:IF[:REQ:RESP]  ISO-TP over CAN (D1) on interface IF; REQ:RESP the 11-bit ids\n"
         "                        in hex, host->LD and LD->host [6C0:6C1]\n"
         "  --tcp tcp:HOST[:PORT]  Ethernet framing (spec 4.1); port 49152 if omitted\n"
         "  --serial serial:TTY[:BAUD]  RS-232 framing (spec 4.2) on TTY (or serial:pty:PATH,\n"
         "                        as ldoem-emud offers it) [115200 baud]\n"
         "Options (default in brackets):\n"
         "  --target T            emulator: assert every byte; device: assert only the positions\n"
         "                        spec 7.2 confirms, skip emulator-only cases [emulator]\n"
         "  --time-scale X        the endpoint's simulated seconds per wall second (ldoem-emud\n"
         "                        --time-scale); timing cases expect wall = simulated / X [1]\n"
         "  --virtual-time        the endpoint runs ldoem-emud --virtual-time: no wall-clock checks,\n"
         "                        device-clock values must match exactly [off]\n"
         "  --strict-timing       a wall-clock case that fails while the machine was too busy to\n"
         "                        keep time is FAIL, not INCONCLUSIVE (a quiet lab machine) [off]\n"
         "  --timeout SECONDS     wall time to wait for one reply (spec 6: S1 waits 5 s) [5]\n"
         "  --filter GLOB         run only cases whose name matches (fnmatch, `*` spans `/`);\n"
         "                        repeatable, any match selects [all]\n"
         "  --exclude GLOB        leave out cases whose name matches, after --filter; repeatable\n"
         "                        (e.g. '*/timing/*' on a sanitizer build, whose wall clock is slow)\n"
         "  --list                print the case names (for the given endpoint, else for all three)\n"
         "  --vectors FILE        spec-section7.yaml to use instead of the compiled-in copy\n"
         "  --verbose, -v         log every telegram on stderr in the text form of protocol/text.hpp\n"
         "  --record FILE         also write every telegram sent and received to FILE (pcapng,\n"
         "                        docs/capture.md): record a real device once, compare later\n"
         "Against a capture (instead of the cases):\n"
         "  --against CAPTURE     send the requests of CAPTURE (pcapng, pcap or candump log; the\n"
         "                        transport with most telegrams) in order and compare each reply\n"
         "                        with the recorded one field by field; prints the differing fields\n"
         "  --port N              the device's TCP port in CAPTURE [the port of the STX \"USP\" frames]\n"
         "  --mask GLOB           leave fields matching GLOB out (e.g. 'profile.sector*.point*.echo');\n"
         "                        repeatable\n"
         "  --mask-times          = --mask '*clock_ms' --mask 'profile.sector*.tstart' --mask 'profile.sector*.tend'\n"
         "  --mask-counters       = --mask profile.sent --mask profile.count\n"
         "  --help, -h            the most used options\n"
         "  --help-all            this text\n"
         "  --version             print the name and version\n"
         "  --completion bash     print a bash completion\n"
         "\n"
         "Output: one line per case, `PASS NAME` or `FAIL NAME: why` followed by an indented hex\n"
         "diff (expected / received / carets under differing bytes, `..` = not asserted), or\n"
         "`INCONCLUSIVE NAME (machine busy: ...): why` for a wall-clock case the machine could not\n"
         "time; then exactly `N passed, M failed, K inconclusive` (inconclusive exits 0).\n"
         "The suite changes the device's configuration (SET_CONFIG global commits to flash) and\n"
         "leaves it in IDLE with the D4 defaults: sensor id 1, 10 Hz, 0.25 deg, sectors 135/225 deg.\n"
         "\n"
         "Exit status:\n"
         "  0        every selected case passed\n"
         "  1        a case failed, or the endpoint could not be opened\n"
         "  2        usage error\n"
         "\n"
         "Examples:\n"
         "  " + p + " --tcp tcp:127.0.0.1:49152 --time-scale 10\n"
         "  " + p + " --can can:vcan0:6C0:6C1 --filter '*/states/*'\n"
         "  " + p + " --serial serial:pty:/tmp/ldoem-serial --filter 'serial/conversation/*'\n"
         "  " + p + " --tcp tcp:192.168.1.10 --target device --timeout 10\n"
         "  " + p + " --tcp tcp:192.168.1.10 --target device --record real-ld.pcapng\n"
         "  " + p + " --tcp tcp:127.0.0.1:49152 --against real-ld.pcapng --mask-times --mask-counters\n";
}

std::string brief_usage_text(std::string_view program_name) {
  return base::brief_help(program_name, usage_text(program_name),
                          "Check a device against the LD-OEM host protocol (docs/conformance.md).",
                          {"--can", "--tcp", "--serial", "--target", "--time-scale", "--timeout", "--filter",
                           "--exclude", "--list", "--record", "--against", "--help", "--version"});
}

}  // namespace ldoem::conformance
