// ldoem-replay: read a capture, cut it into exchanges, serve them through the emulator's
// endpoints until a signal or --timeout (docs/replay.md).
#include <iostream>
#include <string_view>
#include <vector>

#include "ldoem/base/command_line.hpp"
#include "ldoem/capture/capture_reader.hpp"
#include "ldoem/replay/replay_host.hpp"

int main(int argc, char** argv) {
  using namespace ldoem;
  const std::vector<std::string_view> arguments(argv + 1, argv + argc);
  auto options = replay::parse_replay_options(arguments);
  if (!options) {
    std::cerr << ldoem::base::usage_error_line("ldoem-replay", options.error().message);
    return 2;
  }
  if (options->completion_script) {
    std::cout << *options->completion_script;
    return 0;
  }
  if (options->help_all) {
    std::cout << replay::replay_usage_text();
    return 0;
  }
  if (options->help) {
    std::cout << replay::replay_brief_usage_text();
    return 0;
  }
  if (options->version) {
    std::cout << base::version_line("ldoem-replay");
    return 0;
  }
  protocol::ConversationConfig config;
  config.tcp_port = options->capture_tcp_port;  // unset: detected from the frames (docs/replay.md)
  if (!options->endpoints.can_id_pairs.empty()) {
    config.request_can_id = options->endpoints.can_id_pairs.front().request_id;
    config.response_can_id = options->endpoints.can_id_pairs.front().response_id;
  }
  auto loaded = capture::read_capture_conversation(options->capture, config);
  if (!loaded) {
    std::cerr << "ldoem-replay: " << loaded.error() << '\n';
    return 2;
  }
  if (!loaded->warning.empty()) std::cerr << "ldoem-replay: warning: " << loaded->warning << '\n';
  const auto& telegrams = loaded->conversation.telegrams;
  const auto transport = options->transport ? options->transport : protocol::busiest_transport(telegrams);
  if (!transport) {
    std::cerr << "ldoem-replay: " << options->capture.string() << ": no LD-OEM telegram in it\n";
    return 2;
  }
  auto exchanges = protocol::exchanges_of(telegrams, *transport);
  if (exchanges.empty()) {
    std::cerr << "ldoem-replay: " << options->capture.string() << ": no request on " << protocol::transport_name(*transport)
              << '\n';
    return 2;
  }
  const auto& capture_counters = loaded->conversation.counters;
  std::cerr << "ldoem-replay: " << options->capture.string() << ": " << exchanges.size() << " exchanges ("
            << protocol::transport_name(*transport);
  if (*transport == protocol::Transport::tcp) {
    std::cerr << ", device port " << loaded->conversation.tcp_port
              << (loaded->conversation.tcp_port_detected ? " (detected)" : "");
  }
  std::cerr << "); " << capture_counters.packets << " packets, "
            << capture_counters.framing_errors << " framing errors, " << capture_counters.tcp_gaps << " TCP gaps, "
            << capture_counters.ignored_packets << " ignored\n";
  auto host = replay::ReplayHost::create(*options, replay::ReplayDevice(std::move(exchanges), options->speed),
                                         std::cout, std::cerr);
  if (!host) {
    std::cerr << "ldoem-replay: " << host.error().message << '\n';
    return host.error().exit_code;
  }
  const int status = (*host)->run();
  const auto& counters = (*host)->counters();
  std::cerr << "ldoem-replay: requests=" << counters.requests << " in_order=" << counters.in_order
            << " out_of_order=" << counters.out_of_order << " unexpected=" << counters.unexpected << '\n';
  return status;
}
