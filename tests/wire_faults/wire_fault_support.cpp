#include "wire_fault_support.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "ldoem/scene/scene_loader.hpp"

namespace ldoem::wire_faults::test {

FaultyDaemon::FaultyDaemon(const std::string& scene_text, const std::vector<std::string>& extra, bool virtual_time)
    : process(DaemonProcess::start(arguments(scene_text, extra, virtual_time))) {}

std::vector<std::string> FaultyDaemon::arguments(const std::string& scene_text, const std::vector<std::string>& extra,
                                                 bool virtual_time) const {
  std::vector<std::string> all{"--scene", dir.write("scene.yaml", scene_text), "--tcp", "tcp:127.0.0.1:0", "--no-flash",
                               "--event-log", event_log, "--timeout", "100"};
  if (std::find(extra.begin(), extra.end(), "--can") == extra.end()) all.push_back("--no-can");
  if (virtual_time) all.push_back("--virtual-time");
  all.insert(all.end(), extra.begin(), extra.end());
  return all;
}

std::string FaultyDaemon::events() const {
  std::ifstream file(event_log);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

Bytes read_bytes(int fd, std::size_t count, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  Bytes bytes;
  while (bytes.size() < count) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0 || !daemon::test::wait_readable(fd, left)) break;
    std::uint8_t buffer[4096];
    const ssize_t got = ::read(fd, buffer, std::min(sizeof buffer, count - bytes.size()));
    if (got <= 0) break;
    bytes.insert(bytes.end(), buffer, buffer + got);
  }
  return bytes;
}

std::optional<nlohmann::json> control_request(const std::string& path, const nlohmann::json& request,
                                              std::chrono::milliseconds limit) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return std::nullopt;
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, path.c_str(), sizeof(address.sun_path) - 1);
  std::optional<nlohmann::json> answer;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0) {
    const std::string line = request.dump() + "\n";
    if (::send(fd, line.data(), line.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(line.size())) {
      const auto deadline = std::chrono::steady_clock::now() + limit;
      std::string buffer;
      while (!answer) {
        const auto newline = buffer.find('\n');
        if (newline != std::string::npos) {
          const auto parsed = nlohmann::json::parse(buffer.substr(0, newline), nullptr, false);
          buffer.erase(0, newline + 1);
          if (parsed.is_object() && (parsed.contains("return") || parsed.contains("error"))) answer = parsed;
          continue;
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0 || !daemon::test::wait_readable(fd, left)) break;
        char chunk[4096];
        const ssize_t got = ::recv(fd, chunk, sizeof chunk, 0);
        if (got <= 0) break;
        buffer.append(chunk, static_cast<std::size_t>(got));
      }
    }
  }
  ::close(fd);
  return answer;
}

InProcessTcp::InProcessTcp(const std::string& scene_text) {
  auto scene = scene::load_scene_from_string(scene_text, "scene.yaml");
  if (!scene) {
    failure = scene.error().message();
    return;
  }
  daemon::Options options;
  options.can_interface.reset();
  options.tcp = daemon::TcpOption{"127.0.0.1", 0};
  options.flash_mode = daemon::FlashMode::memory;
  options.virtual_time = true;
  auto created = daemon::Daemon::create(std::move(options), std::move(*scene), out, log);
  if (!created) {
    failure = created.error().message;
    return;
  }
  daemon = std::move(*created);
}

InProcessTcp::Arrival InProcessTcp::receive(int fd, std::size_t count, std::chrono::milliseconds wall_limit) {
  Arrival arrival;
  daemon->run_until(
      [&] {
        std::uint8_t buffer[4096];
        const ssize_t got = ::recv(fd, buffer, std::min(sizeof buffer, count - arrival.bytes.size()), MSG_DONTWAIT);
        if (got > 0) {
          arrival.bytes.insert(arrival.bytes.end(), buffer, buffer + got);
          arrival.at = daemon->now();
        }
        return arrival.bytes.size() >= count;
      },
      wall_limit);
  return arrival;
}

}  // namespace ldoem::wire_faults::test
