#include "ldoem/hub/hub_client.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>

namespace ldoem::hub {
namespace {

using driver::Clock;
using driver::fail;
using driver::make_error;
using driver::ok;
using driver::system_error;

int milliseconds_until(Deadline deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 1 << 30));
}

// Connects one resolved address without blocking past the deadline.
Expected<int, DriverError> connect_one(const addrinfo& address, const std::string& object, Deadline deadline) {
  const int fd = ::socket(address.ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    return fail(system_error("socket", object, errno));
  }
  if (::connect(fd, address.ai_addr, address.ai_addrlen) != 0 && errno != EINPROGRESS) {
    const int error = errno;
    ::close(fd);
    return fail(system_error("connect", object, error));
  }
  pollfd entry{fd, POLLOUT, 0};
  if (::poll(&entry, 1, milliseconds_until(deadline)) <= 0) {
    ::close(fd);
    return fail(make_error(ErrorKind::timeout, "connect", object, "no connection before the deadline"));
  }
  int error = 0;
  socklen_t length = sizeof error;
  ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length);
  if (error != 0) {
    ::close(fd);
    return fail(system_error("connect", object, error));
  }
  const int yes = 1;
  (void)::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
  return fd;
}

}  // namespace

Expected<std::unique_ptr<HubClient>, DriverError> HubClient::connect(const ListenAddress& address,
                                                                     std::chrono::milliseconds timeout) {
  const std::string object = "hub:" + address.host + ":" + std::to_string(address.port);
  const Deadline deadline = Clock::now() + timeout;
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(address.port);
  if (const int status = ::getaddrinfo(address.host.c_str(), port.c_str(), &hints, &found); status != 0) {
    return fail(make_error(ErrorKind::invalid_argument, "resolve", object, ::gai_strerror(status)));
  }
  std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> addresses(found, &::freeaddrinfo);
  auto fd = connect_one(*found, object, deadline);
  if (!fd) {
    return fail(fd.error());
  }
  std::unique_ptr<HubClient> client(new HubClient(*fd, object));
  auto greeting = client->receive(deadline);
  if (!greeting) {
    return fail(greeting.error());
  }
  if (!greeting->ok || greeting->command != "HELLO" || !greeting->field("femh")) {
    return fail(make_error(greeting->ok ? ErrorKind::unexpected_reply : error_kind_from_token(greeting->error_kind),
                           "connect", object, format_reply(*greeting)));
  }
  client->frontend_id_ = *greeting->field("femh");
  return client;
}

HubClient::~HubClient() { ::close(fd_); }

driver::Status HubClient::send_line(const std::string& line, Deadline deadline) {
  const std::string bytes = line + "\n";
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t sent = ::send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (sent >= 0) {
      done += static_cast<std::size_t>(sent);
      continue;
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      return fail(system_error("send", name_, errno));
    }
    pollfd entry{fd_, POLLOUT, 0};
    if (::poll(&entry, 1, milliseconds_until(deadline)) <= 0) {
      return fail(make_error(ErrorKind::timeout, "send", name_, "the hub does not read"));
    }
  }
  return ok();
}

Expected<std::string, DriverError> HubClient::read_line(Deadline deadline) {
  for (;;) {
    const std::size_t end = input_.find('\n');
    if (end != std::string::npos) {
      std::string line = input_.substr(0, end);
      input_.erase(0, end + 1);
      return line;
    }
    pollfd entry{fd_, POLLIN, 0};
    const int ready = ::poll(&entry, 1, milliseconds_until(deadline));
    if (ready < 0 && errno == EINTR) {
      continue;
    }
    if (ready <= 0) {
      return fail(make_error(ErrorKind::timeout, "receive", name_, "no reply before the deadline"));
    }
    char buffer[65536];
    const ssize_t got = ::recv(fd_, buffer, sizeof buffer, 0);
    if (got == 0) {
      return fail(make_error(ErrorKind::connection_closed, "receive", name_, "the hub closed the connection"));
    }
    if (got < 0) {
      if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) {
        continue;
      }
      return fail(system_error("recv", name_, errno));
    }
    input_.append(buffer, static_cast<std::size_t>(got));
  }
}

Expected<HubReply, DriverError> HubClient::receive(Deadline deadline) {
  auto line = read_line(deadline);
  if (!line) {
    return fail(line.error());
  }
  auto reply = parse_reply(*line);
  if (!reply) {
    return fail(make_error(ErrorKind::unexpected_reply, "receive", name_, reply.error().detail));
  }
  return std::move(reply.value());
}

Expected<HubReply, DriverError> HubClient::call(const std::string& device, const HubCommand& command,
                                                Deadline deadline) {
  const std::string id = "c" + std::to_string(next_id_++);
  if (auto sent = send_line(format_request(HubRequest{id, device, command}), deadline); !sent) {
    return fail(sent.error());
  }
  for (;;) {
    if (const auto early = early_replies_.find(id); early != early_replies_.end()) {
      HubReply reply = std::move(early->second);
      early_replies_.erase(early);
      return reply;
    }
    auto reply = receive(deadline);
    if (!reply) {
      return fail(reply.error());
    }
    if (reply->id == id) {
      return std::move(reply.value());
    }
    if (reply->id == kUnsolicitedId) {
      keep_notice(std::move(reply.value()));  // a device's FAULT / RECOVERED, not our answer
      continue;
    }
    if (reply->id == kUnknownId) {
      // The hub could not read our id: this is the answer to the line we just sent.
      return std::move(reply.value());
    }
    early_replies_[reply->id] = std::move(reply.value());
  }
}

void HubClient::keep_notice(HubReply notice) {
  if (notices_.size() >= kMaxKeptNotices) {
    notices_.pop_front();  // bounded: the oldest goes
  }
  notices_.push_back(std::move(notice));
}

std::vector<HubReply> HubClient::take_notices() {
  std::vector<HubReply> taken(std::make_move_iterator(notices_.begin()), std::make_move_iterator(notices_.end()));
  notices_.clear();
  return taken;
}

// ---------------------------------------------------------------------------------- HubDevice

HubDevice::HubDevice(std::unique_ptr<HubClient> client, std::string device, HubDeviceOptions options)
    : client_(std::move(client)), device_(std::move(device)), options_(options) {
  object_ = client_->name() + "/" + device_;
}

DriverError HubDevice::bad_reply(const HubReply& reply) const {
  return make_error(ErrorKind::unexpected_reply, reply.command, object_, "reply lacks its fields: " + format_reply(reply));
}

Expected<HubReply, DriverError> HubDevice::call(const HubCommand& command, std::chrono::milliseconds extra_wait) {
  auto reply = client_->call(device_, command, Clock::now() + options_.call_timeout + extra_wait);
  if (!reply) {
    return fail(reply.error());
  }
  if (!reply->ok) {
    return fail(make_error(error_kind_from_token(reply->error_kind), std::string(command_name(command)), object_,
                           reply->error_message));
  }
  return reply;
}

Expected<StatusBlock, DriverError> HubDevice::status_call(const HubCommand& command,
                                                          std::chrono::milliseconds extra_wait) {
  auto reply = call(command, extra_wait);
  if (!reply) {
    return fail(reply.error());
  }
  const auto status = status_from(*reply);
  if (!status) {
    return fail(bad_reply(*reply));
  }
  return *status;
}

Expected<DeviceInfo, DriverError> HubDevice::initialize(const InitializeRequest& request) {
  auto reply = call(request, std::chrono::milliseconds{0});
  if (!reply) {
    return fail(reply.error());
  }
  auto info = info_from(*reply);
  if (!info) {
    return fail(bad_reply(*reply));
  }
  return std::move(*info);
}

Expected<StatusBlock, DriverError> HubDevice::rotate(std::uint16_t frequency_hz) {
  return status_call(RotateCommand{frequency_hz}, driver::kDefaultRotateTimeout);
}

Expected<StatusBlock, DriverError> HubDevice::measure() { return status_call(MeasureCommand{}, {}); }

Expected<StatusBlock, DriverError> HubDevice::idle() {
  return status_call(IdleCommand{}, driver::kDefaultRotateTimeout);
}

Expected<StatusBlock, DriverError> HubDevice::status() {
  return status_call(StatusCommand{std::chrono::milliseconds{0}}, {});
}

Expected<ProfileSample, DriverError> HubDevice::get_profile(std::chrono::milliseconds timeout) {
  auto reply = call(ProfileCommand{std::chrono::milliseconds{0}}, timeout);
  if (!reply) {
    return fail(reply.error());
  }
  auto sample = profile_from(*reply);
  if (!sample) {
    return fail(bad_reply(*reply));
  }
  return std::move(*sample);
}

Expected<TiltPosition, DriverError> HubDevice::move_motor(const MotorMove& move) {
  std::chrono::milliseconds motion{0};
  if (move.step_rate_hz && *move.step_rate_hz > 0.0) {
    motion = std::chrono::milliseconds(static_cast<long long>(std::ceil(1000.0 * move.steps / *move.step_rate_hz)));
  }
  auto reply = call(move, motion);
  if (!reply) {
    return fail(reply.error());
  }
  const auto tilt = tilt_from(*reply);
  if (!tilt) {
    return fail(bad_reply(*reply));
  }
  return *tilt;
}

}  // namespace ldoem::hub
