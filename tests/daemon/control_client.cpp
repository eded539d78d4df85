#include "control_client.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <utility>

#include "host_link.hpp"

namespace ldoem::daemon::test {

using nlohmann::json;

std::optional<ControlClient> ControlClient::connect(const std::string& path) {
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return std::nullopt;
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, path.c_str(), sizeof(address.sun_path) - 1);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    close(fd);
    return std::nullopt;
  }
  return ControlClient(fd);
}

ControlClient::ControlClient(ControlClient&& other) noexcept
    : events(std::move(other.events)), fd_(std::exchange(other.fd_, -1)), buffer_(std::move(other.buffer_)) {}

ControlClient::~ControlClient() {
  if (fd_ >= 0) close(fd_);
}

std::optional<json> ControlClient::next(std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  for (;;) {
    if (const auto newline = buffer_.find('\n'); newline != std::string::npos) {
      const std::string line = buffer_.substr(0, newline);
      buffer_.erase(0, newline + 1);
      return json::parse(line, nullptr, false);
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0 || !wait_readable(fd_, left)) return std::nullopt;
    char chunk[4096];
    const ssize_t got = recv(fd_, chunk, sizeof(chunk), 0);
    if (got <= 0) return std::nullopt;
    buffer_.append(chunk, static_cast<std::size_t>(got));
  }
}

std::optional<json> ControlClient::execute(const json& request) {
  const std::string line = request.dump() + "\n";
  if (send(fd_, line.data(), line.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(line.size())) return std::nullopt;
  while (auto reply = next()) {
    if (reply->contains("event")) {
      events.push_back(*reply);
      continue;
    }
    return reply;
  }
  return std::nullopt;
}

std::optional<json> ControlClient::wait_event(const std::string& name, std::chrono::milliseconds limit,
                                              const std::string& key, const json& value) {
  auto matches = [&](const json& event) {
    return event["event"] == name && (key.empty() || event["data"][key] == value);
  };
  for (const json& seen : events) {
    if (matches(seen)) return seen;
  }
  while (auto line = next(limit)) {
    if (!line->contains("event")) continue;
    events.push_back(*line);
    if (matches(*line)) return *line;
  }
  return std::nullopt;
}

}  // namespace ldoem::daemon::test
