#include "power_test_support.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "host_link.hpp"
#include "ldoem/base/unique_fd.hpp"

namespace ldoem::daemon::test {

using nlohmann::json;

PowerDaemon::PowerDaemon(const std::string& scene_text, const std::vector<std::string>& extra, bool virtual_time) {
  std::vector<std::string> arguments{"--scene", dir.write("scene.yaml", scene_text), "--no-flash",
                                     "--control", control_path, "--timeout", "120"};
  if (virtual_time) arguments.push_back("--virtual-time");
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  if (auto started = DaemonProcess::start(arguments)) process.emplace(std::move(*started));
}

bool PowerDaemon::ready() {
  if (!process || !process->wait_ready()) return false;
  auto connected = ControlClient::connect(control_path);
  if (!connected) return false;
  control.emplace(std::move(*connected));
  return control->next().has_value();
}

bool PowerDaemon::power_cycle(double off_s) {
  const auto reply = control->execute({{"execute", "power-cycle"}, {"arguments", {{"off_s", off_s}}}});
  return reply && reply->contains("return");
}

json PowerDaemon::status() {
  const auto reply = control->execute({{"execute", "query-status"}});
  return reply && reply->contains("return") ? (*reply)["return"] : json::object();
}

double event_seconds(const json& event) {
  const json& stamp = event["timestamp"];
  return stamp["seconds"].get<double>() + stamp["microseconds"].get<double>() * 1e-6;
}

std::string next_on_tcp(int fd, std::chrono::milliseconds limit) {
  if (!wait_readable(fd, limit)) return "nothing";
  char byte = 0;
  const ssize_t got = ::recv(fd, &byte, 1, MSG_DONTWAIT | MSG_PEEK);
  if (got > 0) return "bytes";
  if (got == 0) return "FIN";
  if (errno == ECONNRESET) return "RST";
  return std::strerror(errno);
}

std::string try_connect(std::uint16_t port) {
  const base::UniqueFd fd(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0) return "connected";
  return errno == ECONNREFUSED ? "refused" : std::strerror(errno);
}

std::string scene_with_scanner(const std::string& scanner_keys) {
  return minimal_scene_text() + "scanner: {" + scanner_keys + "}\n";
}

}  // namespace ldoem::daemon::test
