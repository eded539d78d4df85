#include "ldoem/ctl/ctl_client.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <optional>
#include <sstream>

namespace ldoem::ctl {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// Longest line accepted from the daemon (a query-faults answer with many faults fits easily).
constexpr std::size_t kMaxLineBytes = 1 << 20;

class Connection {
 public:
  ~Connection() {
    if (fd_ >= 0) close(fd_);
  }
  std::optional<std::string> open(const std::string& path) {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof(address.sun_path)) return "connect " + path + ": path too long";
    std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
    fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) return std::string("socket: ") + std::strerror(errno);
    if (connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
      return "connect " + path + ": " + std::strerror(errno);
    }
    return std::nullopt;
  }
  bool send_line(const std::string& line) {
    const std::string bytes = line + "\n";
    std::size_t at = 0;
    while (at < bytes.size()) {
      const ssize_t sent = ::send(fd_, bytes.data() + at, bytes.size() - at, MSG_NOSIGNAL);
      if (sent <= 0) return false;
      at += static_cast<std::size_t>(sent);
    }
    return true;
  }
  // The next line, or nothing at the deadline / end of stream (`error` says which).
  std::optional<std::string> read_line(std::optional<Clock::time_point> deadline, std::string& error) {
    for (;;) {
      if (const auto newline = buffer_.find('\n'); newline != std::string::npos) {
        std::string line = buffer_.substr(0, newline);
        buffer_.erase(0, newline + 1);
        return line;
      }
      if (buffer_.size() > kMaxLineBytes) {
        error = "reply line too long";
        return std::nullopt;
      }
      int wait_ms = -1;
      if (deadline) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(*deadline - Clock::now()).count();
        if (left <= 0) {
          error = "timed out";
          return std::nullopt;
        }
        wait_ms = static_cast<int>(std::min<long long>(left, 60'000));
      }
      pollfd entry{fd_, POLLIN, 0};
      const int ready = poll(&entry, 1, wait_ms);
      if (ready < 0 && errno != EINTR) {
        error = std::string("poll: ") + std::strerror(errno);
        return std::nullopt;
      }
      if (ready <= 0) continue;
      char chunk[4096];
      const ssize_t got = recv(fd_, chunk, sizeof(chunk), 0);
      if (got <= 0) {
        error = "the daemon closed the connection";
        return std::nullopt;
      }
      buffer_.append(chunk, static_cast<std::size_t>(got));
    }
  }

 private:
  int fd_ = -1;
  std::string buffer_;
};

std::string seconds_text(const json& timestamp) {
  std::ostringstream text;
  text << timestamp.value("seconds", 0LL) << "." ;
  const std::string micros = std::to_string(timestamp.value("microseconds", 0LL));
  text << std::string(6 - std::min<std::size_t>(6, micros.size()), '0') << micros;
  return text.str();
}

void key_values(const json& object, const std::string& prefix, std::ostringstream& text) {
  for (const auto& [key, value] : object.items()) {
    if (value.is_object()) {
      key_values(value, prefix + key + ".", text);
    } else {
      text << prefix << key << ": " << (value.is_string() ? value.get<std::string>() : value.dump()) << "\n";
    }
  }
}

}  // namespace

std::string human_text(const json& line) {
  std::ostringstream text;
  if (line.contains("error")) {
    text << "error " << line["error"].value("class", "?") << ": " << line["error"].value("desc", "") << "\n";
  } else if (line.contains("event")) {
    text << seconds_text(line.value("timestamp", json::object())) << " " << line["event"].get<std::string>();
    if (line.contains("data")) text << " " << line["data"].dump();
    text << "\n";
  } else if (line.contains("return")) {
    const json& value = line["return"];
    if (value.is_array()) {
      if (value.empty()) text << "none\n";
      for (const json& item : value) text << (item.contains("description") ? item["description"].get<std::string>() : item.dump()) << "\n";
    } else if (value.is_object() && value.empty()) {
      text << "ok\n";
    } else if (value.is_object()) {
      key_values(value, "", text);
    } else {
      text << value.dump() << "\n";
    }
  } else {
    text << line.dump() << "\n";
  }
  return text.str();
}

int run_ctl(const CtlPlan& plan, std::ostream& out, std::ostream& err) {
  Connection connection;
  if (auto problem = connection.open(plan.control_path)) {
    err << "ldoem-ctl: " << *problem << "\n";
    return kExitFailure;
  }
  const auto start = Clock::now();
  auto deadline = [&]() -> std::optional<Clock::time_point> {
    if (plan.timeout.count() == 0) return std::nullopt;
    return start + plan.timeout;
  };
  std::string error;
  auto greeting = connection.read_line(deadline(), error);
  if (!greeting) {
    err << "ldoem-ctl: " << plan.control_path << ": no greeting: " << error << "\n";
    return kExitFailure;
  }
  const json greeting_json = json::parse(*greeting, nullptr, false);
  if (greeting_json.is_discarded() || !greeting_json.contains("QMP")) {
    err << "ldoem-ctl: " << plan.control_path << ": not an ldoem control socket\n";
    return kExitFailure;
  }
  if (plan.follow_events) {
    std::uint64_t seen = 0;
    while (!plan.event_count || seen < *plan.event_count) {
      auto line = connection.read_line(deadline(), error);
      if (!line) {
        if (error == "timed out") return kExitOk;  // followed as long as asked
        err << "ldoem-ctl: " << error << "\n";
        return kExitFailure;
      }
      const json parsed = json::parse(*line, nullptr, false);
      if (parsed.is_discarded() || !parsed.contains("event")) continue;
      out << (plan.json_output ? *line + "\n" : human_text(parsed)) << std::flush;
      ++seen;
    }
    return kExitOk;
  }
  json request = *plan.request;
  request["id"] = "ldoem-ctl";
  if (!connection.send_line(request.dump())) {
    err << "ldoem-ctl: send: the daemon closed the connection\n";
    return kExitFailure;
  }
  for (;;) {
    auto line = connection.read_line(deadline(), error);
    if (!line) {
      err << "ldoem-ctl: " << request.value("execute", "request") << ": " << error << "\n";
      return kExitFailure;
    }
    const json parsed = json::parse(*line, nullptr, false);
    if (parsed.is_discarded()) continue;
    if (parsed.contains("event")) continue;  // events of other work; `events` follows them
    if (plan.json_output) {
      out << *line << "\n";
    } else {
      (parsed.contains("error") ? err : out) << human_text(parsed);
    }
    return parsed.contains("error") ? kExitFailure : kExitOk;
  }
}

}  // namespace ldoem::ctl
