#include "scenario_device.hpp"

#include <thread>

namespace ldoem::fault_scenarios {

void RunningScene::wait_until_s(double seconds) const {
  const auto target = ready_at + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  std::this_thread::sleep_until(target);
}

std::string scenario(const std::string& name) { return std::string(LDOEM_SOURCE_DIR) + "/scenes/faults/" + name + ".yaml"; }

std::optional<RunningScene> start_scene(const std::string& scene, const std::vector<std::string>& extra,
                                        std::string* failure) {
  // --timeout: the daemon stops by itself should the test die.
  std::vector<std::string> arguments{"--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash", "--timeout", "170"};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  auto daemon = daemon::test::DaemonProcess::start(arguments);
  if (!daemon || !daemon->wait_ready(std::chrono::seconds(60))) {
    if (failure) *failure = daemon ? daemon->stderr_text() : "cannot start ldoem-emud";
    return std::nullopt;
  }
  const auto ready_at = Clock::now();
  const std::uint16_t port = daemon->tcp_port();
  return RunningScene{std::move(*daemon), ready_at, driver::TcpEndpoint{"127.0.0.1", port}};
}

std::unique_ptr<driver::Scanner> connect_scanner(const RunningScene& scene, driver::ScannerOptions options) {
  const driver::Endpoint endpoint{scene.endpoint};
  options.reopen = [endpoint] { return driver::open_transport(endpoint); };
  auto transport = driver::open_transport(endpoint);
  if (!transport) return nullptr;
  auto scanner = std::make_unique<driver::Scanner>(std::move(transport.value()), std::move(options));
  if (!scanner->connect()) return nullptr;
  return scanner;
}

}  // namespace ldoem::fault_scenarios
