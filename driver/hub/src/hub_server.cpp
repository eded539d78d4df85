#include "ldoem/hub/hub_server.hpp"

#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <deque>
#include <map>
#include <mutex>
#include <unordered_map>

#include "ldoem/hub/backend_handler.hpp"
#include "ldoem/hub/hub_protocol.hpp"

namespace ldoem::hub {
namespace {

using driver::fail;
using driver::ok;
using driver::system_error;

// epoll tags; client tags start above them and are never reused.
constexpr std::uint64_t kListenTag = 1;
constexpr std::uint64_t kWakeTag = 2;
constexpr std::uint64_t kExtraStopTag = 3;
constexpr std::uint64_t kFirstClientTag = 16;

struct Client {
  int fd = -1;
  std::string frontend_id;  // FEMH id
  std::string input;
  std::string output;
  bool discarding_long_line = false;
  bool waiting_for_writable = false;
  std::map<std::string, std::size_t> in_flight;  // device -> requests queued or running
  std::shared_ptr<std::atomic<bool>> alive = std::make_shared<std::atomic<bool>>(true);
};

}  // namespace

struct Hub::Impl {
  HubSettings settings;
  std::vector<std::unique_ptr<BackEndHandler>> handlers;
  std::unordered_map<std::string, BackEndHandler*> handler_by_device;

  int listen_fd = -1;
  int epoll_fd = -1;
  int wake_fd = -1;
  std::uint16_t bound_port = 0;
  std::atomic<bool> stop_requested{false};

  std::mutex completions_mutex;
  std::deque<BackendResult> completions;

  std::unordered_map<std::uint64_t, Client> clients;  // by epoll tag
  std::unordered_map<std::string, std::uint64_t> tag_by_frontend;
  std::uint64_t next_tag = kFirstClientTag;
  std::uint64_t next_frontend_number = 1;
  HubCounters counters;

  Impl(HubSettings hub_settings, std::vector<DeviceSlot> devices) : settings(std::move(hub_settings)) {
    wake_fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    std::size_t number = 1;
    for (DeviceSlot& slot : devices) {
      BackendSettings backend{settings.queue_capacity, slot.profile_timeout};
      auto handler = std::make_unique<BackEndHandler>("B" + std::to_string(number++), slot.name,
                                                      std::move(slot.device), backend,
                                                      [this](BackendResult result) { complete(std::move(result)); });
      handler_by_device[slot.name] = handler.get();
      handlers.push_back(std::move(handler));
    }
  }

  ~Impl() {
    handlers.clear();  // joins the workers before the queue they post to goes away
    for (auto& [tag, client] : clients) {
      ::close(client.fd);
    }
    for (int fd : {listen_fd, epoll_fd, wake_fd}) {
      if (fd >= 0) {
        ::close(fd);
      }
    }
  }

  // Worker threads.
  void complete(BackendResult result) {
    {
      std::lock_guard lock(completions_mutex);
      completions.push_back(std::move(result));
    }
    wake();
  }

  void wake() const {
    const std::uint64_t one = 1;
    (void)!::write(wake_fd, &one, sizeof one);
  }

  // ------------------------------------------------------------------------ the loop's side
  driver::Status listen() {
    const std::string object = settings.listen.host + ":" + std::to_string(settings.listen.port);
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
    addrinfo* found = nullptr;
    const std::string port = std::to_string(settings.listen.port);
    if (const int status = ::getaddrinfo(settings.listen.host.c_str(), port.c_str(), &hints, &found); status != 0) {
      return fail(driver::make_error(driver::ErrorKind::invalid_argument, "resolve", object, ::gai_strerror(status)));
    }
    std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> addresses(found, &::freeaddrinfo);
    listen_fd = ::socket(found->ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (listen_fd < 0) {
      return fail(system_error("socket", object, errno));
    }
    const int yes = 1;
    (void)::setsockopt(listen_fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(listen_fd, found->ai_addr, found->ai_addrlen) != 0) {
      return fail(system_error("bind", object, errno));
    }
    if (::listen(listen_fd, 64) != 0) {
      return fail(system_error("listen", object, errno));
    }
    sockaddr_storage bound{};
    socklen_t length = sizeof bound;
    ::getsockname(listen_fd, reinterpret_cast<sockaddr*>(&bound), &length);
    bound_port = bound.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port)
                                             : ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
    epoll_fd = ::epoll_create1(EPOLL_CLOEXEC);
    if (epoll_fd < 0 || wake_fd < 0) {
      return fail(system_error("epoll_create1", object, errno));
    }
    add_watch(listen_fd, kListenTag, EPOLLIN);
    add_watch(wake_fd, kWakeTag, EPOLLIN);
    return ok();
  }

  void add_watch(int fd, std::uint64_t tag, std::uint32_t events) const {
    epoll_event event{};
    event.events = events;
    event.data.u64 = tag;
    (void)::epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &event);
  }

  driver::Status run(int extra_stop_fd) {
    if (epoll_fd < 0) {
      return fail(driver::make_error(driver::ErrorKind::wrong_state, "run", "hub", "listen() first"));
    }
    if (extra_stop_fd >= 0) {
      add_watch(extra_stop_fd, kExtraStopTag, EPOLLIN);
    }
    epoll_event events[64];
    while (!stop_requested.load()) {
      const int count = ::epoll_wait(epoll_fd, events, 64, -1);
      if (count < 0) {
        if (errno == EINTR) {
          continue;
        }
        return fail(system_error("epoll_wait", "hub", errno));
      }
      for (int i = 0; i < count; ++i) {
        const std::uint64_t tag = events[i].data.u64;
        if (tag == kListenTag) {
          accept_clients();
        } else if (tag == kWakeTag) {
          std::uint64_t ignored = 0;
          (void)!::read(wake_fd, &ignored, sizeof ignored);
          deliver_completions();
        } else if (tag == kExtraStopTag) {
          stop_requested.store(true);
        } else {
          serve_client(tag, events[i].events);
        }
      }
    }
    if (extra_stop_fd >= 0) {
      (void)::epoll_ctl(epoll_fd, EPOLL_CTL_DEL, extra_stop_fd, nullptr);
    }
    return ok();
  }

  void accept_clients() {
    for (;;) {
      const int fd = ::accept4(listen_fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) {
        return;  // EAGAIN: all taken; other errors: the client is gone already
      }
      if (clients.size() >= settings.max_clients) {
        const std::string line = format_reply(error_reply(std::string(kUnsolicitedId), "busy",
                                                          "the hub serves at most " +
                                                              std::to_string(settings.max_clients) + " clients")) +
                                 "\n";
        (void)!::send(fd, line.data(), line.size(), MSG_NOSIGNAL);
        ::close(fd);
        continue;
      }
      const int yes = 1;
      (void)::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
      const std::uint64_t tag = next_tag++;
      Client& client = clients[tag];
      client.fd = fd;
      client.frontend_id = "F" + std::to_string(next_frontend_number++);
      tag_by_frontend[client.frontend_id] = tag;
      ++counters.clients_accepted;
      add_watch(fd, tag, EPOLLIN | EPOLLRDHUP);
      send_reply(tag, ok_reply(std::string(kUnsolicitedId), "HELLO",
                               {{"femh", client.frontend_id}, {"protocol", std::to_string(kHubProtocolVersion)}}));
    }
  }

  void drop_client(std::uint64_t tag) {
    const auto found = clients.find(tag);
    if (found == clients.end()) {
      return;
    }
    found->second.alive->store(false);
    (void)::epoll_ctl(epoll_fd, EPOLL_CTL_DEL, found->second.fd, nullptr);
    ::close(found->second.fd);
    tag_by_frontend.erase(found->second.frontend_id);
    clients.erase(found);
  }

  void serve_client(std::uint64_t tag, std::uint32_t events) {
    if ((events & EPOLLOUT) != 0) {
      flush(tag);
    }
    if ((events & (EPOLLIN | EPOLLHUP | EPOLLERR | EPOLLRDHUP)) != 0) {
      read_client(tag);
    }
  }

  void read_client(std::uint64_t tag) {
    char buffer[4096];
    for (;;) {
      const auto found = clients.find(tag);
      if (found == clients.end()) {
        return;
      }
      const ssize_t got = ::recv(found->second.fd, buffer, sizeof buffer, 0);
      if (got == 0 || (got < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
        drop_client(tag);
        return;
      }
      if (got < 0) {
        if (errno == EINTR) {
          continue;
        }
        return;
      }
      found->second.input.append(buffer, static_cast<std::size_t>(got));
      take_lines(tag);
    }
  }

  void take_lines(std::uint64_t tag) {
    for (;;) {
      const auto found = clients.find(tag);
      if (found == clients.end()) {
        return;
      }
      Client& client = found->second;
      const std::size_t end = client.input.find('\n');
      if (end == std::string::npos) {
        if (client.input.size() > kMaxRequestLineLength) {
          if (!client.discarding_long_line) {
            send_reply(tag, error_reply(std::string(kUnknownId), "bad_request",
                                        "request line longer than " + std::to_string(kMaxRequestLineLength) +
                                            " bytes"));
          }
          client.discarding_long_line = true;
          client.input.clear();
        }
        return;
      }
      std::string line = client.input.substr(0, end);
      client.input.erase(0, end + 1);
      if (client.discarding_long_line) {
        client.discarding_long_line = false;
        continue;
      }
      if (line.size() > kMaxRequestLineLength) {
        send_reply(tag, error_reply(std::string(kUnknownId), "bad_request", "request line too long"));
        continue;
      }
      handle_line(tag, line);
    }
  }

  void handle_line(std::uint64_t tag, const std::string& line) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) {
      return;  // blank lines are ignored (handy with netcat)
    }
    ++counters.requests;
    auto request = parse_request(line);
    if (!request) {
      ++counters.errors;
      send_reply(tag, error_reply(request.error().id, request.error().kind, request.error().detail));
      return;
    }
    if (std::holds_alternative<DevicesCommand>(request->command)) {
      std::string list;
      for (const auto& handler : handlers) {
        list += (list.empty() ? "" : ",") + handler->device_name() + ":" + handler->handler_id();
      }
      send_reply(tag, ok_reply(request->id, "DEVICES", {{"devices", list}}));
      return;
    }
    const auto device = handler_by_device.find(request->device);
    if (device == handler_by_device.end()) {
      ++counters.errors;
      send_reply(tag, error_reply(request->id, "unknown_device", "no device named `" + request->device + "`"));
      return;
    }
    if (answer_from_cache(tag, *request, *device->second)) {
      ++counters.answered_from_cache;
      return;
    }
    Client& client = clients.at(tag);
    if (!device->second->submit(BackendJob{client.frontend_id, client.alive, *request})) {
      ++counters.errors;
      send_reply(tag, error_reply(request->id, "busy",
                                  request->device + " (" + device->second->handler_id() + "): request queue is full"));
      return;
    }
    ++counters.forwarded;
    ++client.in_flight[request->device];
  }

  bool answer_from_cache(std::uint64_t tag, const HubRequest& request, const BackEndHandler& handler) {
    std::optional<std::chrono::milliseconds> asked;
    if (const auto* status = std::get_if<StatusCommand>(&request.command)) {
      asked = status->max_age;
    } else if (const auto* profile = std::get_if<ProfileCommand>(&request.command)) {
      asked = profile->max_age;
    } else {
      return false;
    }
    const std::chrono::milliseconds max_age = asked.value_or(settings.max_age);
    const Client& client = clients.at(tag);
    const auto in_flight = client.in_flight.find(request.device);
    if (max_age.count() <= 0 || (in_flight != client.in_flight.end() && in_flight->second > 0)) {
      return false;
    }
    const auto now = Clock::now();
    std::vector<ReplyField> fields;
    Clock::time_point taken_at;
    if (std::holds_alternative<StatusCommand>(request.command)) {
      const auto cached = handler.latest_status();
      if (!cached) {
        return false;
      }
      fields = status_fields(cached->status);
      taken_at = cached->taken_at;
    } else {
      const auto cached = handler.latest_profile();
      if (!cached) {
        return false;
      }
      fields = profile_fields(cached->sample);
      taken_at = cached->taken_at;
    }
    const auto age = std::chrono::duration_cast<std::chrono::milliseconds>(now - taken_at);
    if (age > max_age) {
      return false;
    }
    fields.emplace_back("handler", handler.handler_id());
    fields.emplace_back("source", "cache");
    fields.emplace_back("age_ms", std::to_string(age.count()));
    send_reply(tag, ok_reply(request.id, std::string(command_name(request.command)), std::move(fields)));
    return true;
  }

  void deliver_completions() {
    std::deque<BackendResult> ready;
    {
      std::lock_guard lock(completions_mutex);
      ready.swap(completions);
    }
    for (BackendResult& result : ready) {
      const auto tag = tag_by_frontend.find(result.frontend_id);
      if (tag == tag_by_frontend.end()) {
        continue;  // the client left; its reply has nobody to go to
      }
      Client& client = clients.at(tag->second);
      if (auto in_flight = client.in_flight.find(result.device);
          in_flight != client.in_flight.end() && in_flight->second > 0) {
        --in_flight->second;
      }
      if (!result.reply.ok) {
        ++counters.errors;
      }
      send_reply(tag->second, result.reply);
    }
  }

  void send_reply(std::uint64_t tag, const HubReply& reply) {
    const auto found = clients.find(tag);
    if (found == clients.end()) {
      return;
    }
    found->second.output += format_reply(reply);
    found->second.output += '\n';
    if (found->second.output.size() > settings.max_output_bytes) {
      drop_client(tag);
      return;
    }
    flush(tag);
  }

  void flush(std::uint64_t tag) {
    const auto found = clients.find(tag);
    if (found == clients.end()) {
      return;
    }
    Client& client = found->second;
    while (!client.output.empty()) {
      const ssize_t sent = ::send(client.fd, client.output.data(), client.output.size(), MSG_NOSIGNAL);
      if (sent < 0) {
        if (errno == EINTR) {
          continue;
        }
        if (errno == EAGAIN || errno == EWOULDBLOCK) {
          break;
        }
        drop_client(tag);
        return;
      }
      client.output.erase(0, static_cast<std::size_t>(sent));
    }
    const bool want_writable = !client.output.empty();
    if (want_writable != client.waiting_for_writable) {
      epoll_event event{};
      event.events = EPOLLIN | EPOLLRDHUP | (want_writable ? EPOLLOUT : 0u);
      event.data.u64 = tag;
      (void)::epoll_ctl(epoll_fd, EPOLL_CTL_MOD, client.fd, &event);
      client.waiting_for_writable = want_writable;
    }
  }
};

Hub::Hub(HubSettings settings, std::vector<DeviceSlot> devices)
    : impl_(std::make_unique<Impl>(std::move(settings), std::move(devices))) {}

Hub::~Hub() = default;

driver::Status Hub::listen() { return impl_->listen(); }

std::uint16_t Hub::port() const { return impl_->bound_port; }

driver::Status Hub::run(int extra_stop_fd) { return impl_->run(extra_stop_fd); }

void Hub::request_stop() {
  impl_->stop_requested.store(true);
  impl_->wake();
}

std::vector<std::pair<std::string, std::string>> Hub::devices() const {
  std::vector<std::pair<std::string, std::string>> list;
  for (const auto& handler : impl_->handlers) {
    list.emplace_back(handler->device_name(), handler->handler_id());
  }
  return list;
}

HubCounters Hub::counters() const { return impl_->counters; }

}  // namespace ldoem::hub
