// A client of ldoem-emud's control socket for the daemon tests: JSON lines with bounded waits.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ldoem::daemon::test {

class ControlClient {
 public:
  static std::optional<ControlClient> connect(const std::string& path);
  ControlClient(ControlClient&& other) noexcept;
  ControlClient& operator=(ControlClient&&) = delete;
  ~ControlClient();
  // The next line (an event or a reply), or nothing after `limit`.
  std::optional<nlohmann::json> next(std::chrono::milliseconds limit = std::chrono::seconds(5));
  // Sends a request and returns its reply, keeping the events seen meanwhile.
  std::optional<nlohmann::json> execute(const nlohmann::json& request);
  // Reads lines until an event named `name` whose data has `key` == `value` when given.
  std::optional<nlohmann::json> wait_event(const std::string& name,
                                           std::chrono::milliseconds limit = std::chrono::seconds(5),
                                           const std::string& key = "", const nlohmann::json& value = nullptr);
  std::vector<nlohmann::json> events;

 private:
  explicit ControlClient(int fd) : fd_(fd) {}
  int fd_ = -1;
  std::string buffer_;
};

}  // namespace ldoem::daemon::test
