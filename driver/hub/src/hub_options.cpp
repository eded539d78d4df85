#include "ldoem/hub/hub_options.hpp"

#include "ldoem/base/command_line.hpp"
#include "ldoem/base/numbers.hpp"

namespace ldoem::hub {
namespace {

using base::Unexpected;

// Large enough for any sane setting, small enough that no later arithmetic overflows.
constexpr std::uint64_t kMaxCount = 1'000'000;
constexpr std::uint64_t kMaxTimeoutMs = 7ULL * 24 * 3600 * 1000;

// A count option's check: a whole number in [1, kMaxCount], stored in `slot`.
auto count_into(std::size_t& slot) {
  return [&slot](const std::string& value) -> std::optional<std::string> {
    const auto count = base::parse_integer<std::uint64_t>(value);
    if (!count || *count == 0 || *count > kMaxCount) {
      return "`" + value + "` is not a number in [1, " + std::to_string(kMaxCount) + "]";
    }
    slot = static_cast<std::size_t>(*count);
    return std::nullopt;
  };
}

}  // namespace

base::Expected<HubCommandLine, std::string> parse_hub_command_line(const std::vector<std::string_view>& args) {
  HubCommandLine line;
  base::CommandLine command_line("ldoem-hub");
  CLI::App& app = command_line.app();
  app.add_option("--config", line.config_path);
  base::take_text(app, "--listen", [&line](const std::string& value) -> std::optional<std::string> {
    auto address = parse_listen_address(value);
    if (!address) {
      return address.error();
    }
    line.listen = address.value();
    return std::nullopt;
  });
  base::take_text(app, "--max-age-ms", [&line](const std::string& value) -> std::optional<std::string> {
    const auto age = base::parse_integer<std::uint64_t>(value);
    if (!age || *age > kMaxTimeoutMs) {
      return "`" + value + "` is not a number of milliseconds";
    }
    line.max_age = std::chrono::milliseconds(*age);
    return std::nullopt;
  });
  base::take_text(app, "--max-clients", count_into(line.max_clients));
  base::take_text(app, "--queue", count_into(line.queue_capacity));
  base::take_text(app, "--max-in-flight", count_into(line.max_in_flight));
  base::take_text(app, "--idle-timeout-ms", [&line](const std::string& value) -> std::optional<std::string> {
    const auto timeout = base::parse_integer<std::uint64_t>(value);
    if (!timeout || *timeout > kMaxTimeoutMs) {
      return "`" + value + "` is not a number of milliseconds in [0, " + std::to_string(kMaxTimeoutMs) + "]";
    }
    line.idle_timeout = std::chrono::milliseconds(*timeout);
    return std::nullopt;
  });
  if (auto problem = command_line.parse(args)) {
    return Unexpected(*problem);
  }
  line.help = command_line.help_requested();
  line.help_all = command_line.help_all_requested();
  line.version = command_line.version_requested();
  if (line.version) return line;
  if (command_line.completion_requested()) {
    line.completion_script = command_line.completion_script();
  }
  if (!line.help && !line.help_all && !line.completion_script && line.config_path.empty()) {
    return Unexpected(std::string("--config FILE is required"));
  }
  return line;
}

std::string hub_usage(std::string_view program) {
  std::string text = "usage: " + std::string(program) + " --config FILE [options]\n";
  text += R"(
The generic interface of the 3D scanner: many clients, many devices, one line protocol
(docs/hub.md). Each client gets a front-end handler (F1, F2, ...), each device a back-end
handler (B1, B2, ...) that serialises access to it.

Options:
  --config FILE        YAML device list (name, scanner endpoint, lpt endpoint, stepper);
                       required
  --listen HOST:PORT   where clients connect (default: the file's `listen`, else
                       127.0.0.1:49200; the hub has no authentication, keep it on loopback)
  --max-age-ms N       STATUS and GET2DPROFILE are answered from the device's latest data
                       when it is at most N ms old (default: the file's, else 50; 0: never)
  --max-clients N      connections served at once (default 64; more get `* ERR busy`)
  --idle-timeout-ms N  a client with no request in flight that sends nothing for N ms is
                       told `* ERR timeout` and closed (default 60000; 0: never)
  --max-in-flight N    requests one client may have queued or running (default 16; more
                       answer ERR busy), so no client fills a device's queue
  --queue N            requests queued per device (default 256; more answer ERR busy)
  --help               the most used options
  --help-all           this text
  --version            print the name and version
  --completion bash    print a bash completion (source <(ldoem-hub --completion bash))

Exit codes: 0 stopped normally, 1 runtime failure (cannot listen), 2 usage or configuration
error, 128+N after signal N (SIGINT, SIGTERM).

Examples:
  ldoem-hub --config hub.yaml
  ldoem-hub --config hub.yaml --listen 127.0.0.1:49201 --max-age-ms 0
  printf '1 left INITIALIZE\n2 left STATUS\n' | nc -q1 127.0.0.1 49200
)";
  return text;
}

std::string hub_brief_usage(std::string_view program) {
  return base::brief_help(program, hub_usage(program), "Serve LD-OEM scanners to many clients over one line protocol (docs/hub.md).",
                          {"--config", "--listen", "--max-age-ms", "--max-clients", "--help", "--version"});
}

}  // namespace ldoem::hub
