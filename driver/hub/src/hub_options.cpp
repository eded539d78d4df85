#include "ldoem/hub/hub_options.hpp"

#include "ldoem/base/numbers.hpp"

namespace ldoem::hub {
namespace {

using protocol::Unexpected;

std::optional<unsigned long long> parse_count(std::string_view text) {
  return base::parse_integer<unsigned long long>(text);
}

// Large enough for any sane setting, small enough that no later arithmetic overflows.
constexpr unsigned long long kMaxCount = 1'000'000;
constexpr unsigned long long kMaxTimeoutMs = 7ULL * 24 * 3600 * 1000;

}  // namespace

protocol::Expected<HubCommandLine, std::string> parse_hub_command_line(const std::vector<std::string_view>& args) {
  HubCommandLine line;
  const auto usage_error = [](std::string text) { return Unexpected<std::string>(std::move(text)); };
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string_view option = args[i];
    if (option == "--help" || option == "-h") {
      line.help = true;
      continue;
    }
    if (i + 1 >= args.size()) {
      return usage_error(option.starts_with("--") ? std::string(option) + " needs a value"
                                                  : "unknown argument `" + std::string(option) + "`");
    }
    const std::string_view value = args[++i];
    if (option == "--config") {
      line.config_path = std::string(value);
    } else if (option == "--listen") {
      auto address = parse_listen_address(value);
      if (!address) {
        return usage_error("--listen: " + address.error());
      }
      line.listen = address.value();
    } else if (option == "--max-age-ms") {
      const auto age = parse_count(value);
      if (!age || *age > kMaxTimeoutMs) {
        return usage_error("--max-age-ms: `" + std::string(value) + "` is not a number of milliseconds");
      }
      line.max_age = std::chrono::milliseconds(*age);
    } else if (option == "--max-clients" || option == "--queue" || option == "--max-in-flight") {
      const auto count = parse_count(value);
      if (!count || *count == 0 || *count > kMaxCount) {
        return usage_error(std::string(option) + ": `" + std::string(value) + "` is not a number in [1, " +
                           std::to_string(kMaxCount) + "]");
      }
      std::size_t& target = option == "--queue"           ? line.queue_capacity
                            : option == "--max-in-flight" ? line.max_in_flight
                                                          : line.max_clients;
      target = static_cast<std::size_t>(*count);
    } else if (option == "--idle-timeout-ms") {
      const auto timeout = parse_count(value);
      if (!timeout || *timeout > kMaxTimeoutMs) {
        return usage_error("--idle-timeout-ms: `" + std::string(value) + "` is not a number of milliseconds in [0, " +
                           std::to_string(kMaxTimeoutMs) + "]");
      }
      line.idle_timeout = std::chrono::milliseconds(*timeout);
    } else {
      return usage_error("unknown option `" + std::string(option) + "`");
    }
  }
  if (!line.help && line.config_path.empty()) {
    return usage_error("--config FILE is required");
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
  --help               this text

Exit codes: 0 stopped normally, 1 runtime failure (cannot listen), 2 usage or configuration
error, 128+N after signal N (SIGINT, SIGTERM).

Examples:
  ldoem-hub --config hub.yaml
  ldoem-hub --config hub.yaml --listen 127.0.0.1:49201 --max-age-ms 0
  printf '1 left INITIALIZE\n2 left STATUS\n' | nc -q1 127.0.0.1 49200
)";
  return text;
}

}  // namespace ldoem::hub
