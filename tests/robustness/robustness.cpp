#include "robustness.hpp"

#include <cstdlib>

namespace ldoem::daemon::test {

HostileRun::HostileRun(std::vector<std::string> transport_arguments) {
  const std::string scene = dir.write("scene.yaml", minimal_scene_text());
  std::vector<std::string> arguments{"--scene", scene, "--no-flash", "--timeout", "600"};
  arguments.insert(arguments.end(), transport_arguments.begin(), transport_arguments.end());
  if (auto started = DaemonProcess::start(arguments)) process.emplace(std::move(*started));
}

::testing::AssertionResult HostileRun::ready() {
  if (!process) return ::testing::AssertionFailure() << "ldoem-emud did not start";
  if (!process->wait_ready()) return ::testing::AssertionFailure() << "not ready: " << process->stderr_text();
  const auto rss = process->rss_kib();
  if (!rss) return ::testing::AssertionFailure() << "no VmRSS for pid " << process->pid();
  start_rss_kib = *rss;
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult still_healthy(DaemonProcess& process, std::uint64_t start_rss_kib) {
  if (!process.alive()) {
    return ::testing::AssertionFailure() << "ldoem-emud exited with " << process.wait(std::chrono::milliseconds(0)).value_or(-1)
                                         << "; stderr: " << process.stderr_text();
  }
  const auto rss = process.rss_kib();
  if (!rss) return ::testing::AssertionFailure() << "no VmRSS";
  const std::uint64_t bound = 2 * start_rss_kib + kRssSlackKib;
  if (*rss > bound) {
    return ::testing::AssertionFailure() << "VmRSS " << *rss << " kB over the bound " << bound << " kB (start "
                                         << start_rss_kib << " kB)";
  }
  return ::testing::AssertionSuccess() << "VmRSS " << *rss << " kB (start " << start_rss_kib << " kB)";
}

Bytes random_bytes(std::mt19937_64& generator, std::size_t count) {
  Bytes bytes(count);
  for (auto& byte : bytes) byte = static_cast<std::uint8_t>(generator());
  return bytes;
}

double flood_seconds(double fallback) {
  if (const char* text = std::getenv("LDOEM_FLOOD_SECONDS")) {
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end != text && value > 0) return value;
  }
  return fallback;
}

Bytes idle_status_reply() { return telegram("GET_STATUS reply 0000 0001"); }

}  // namespace ldoem::daemon::test
