#include "ldoem/hub/hub_server.hpp"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <iostream>

#include "hub_impl.hpp"
#include "listen_socket.hpp"

namespace ldoem::hub {

using driver::fail;
using driver::ok;
using driver::system_error;
using std::chrono::milliseconds;

namespace {

// A warning through the hub's own warn hook, or on stderr.
void say_warning(const std::function<void(const std::string&)>& warn, const std::string& line) {
  if (warn) {
    warn(line);
  } else {
    std::cerr << "ldoem-hub: warn: " << line << "\n";
  }
}

}  // namespace

void Hub::Impl::complete(BackendResult result) {
  {
    std::lock_guard lock(completions_mutex);
    completions.push_back(std::move(result));
  }
  wake();
}

driver::Status Hub::Impl::listen() {
  auto socket = open_listening_socket(settings.listen);
  if (!socket) {
    return fail(socket.error());
  }
  listen_fd = socket->fd;
  bound_port = socket->port;
  epoll_fd = ::epoll_create1(EPOLL_CLOEXEC);
  if (epoll_fd < 0 || wake_fd < 0) {
    return fail(system_error("epoll_create1", "hub", errno));
  }
  watch(EPOLL_CTL_ADD, listen_fd, kListenTag, EPOLLIN);
  watch(EPOLL_CTL_ADD, wake_fd, kWakeTag, EPOLLIN);
  return ok();
}

void Hub::Impl::watch(int operation, int fd, std::uint64_t tag, std::uint32_t events) const {
  epoll_event event{};
  event.events = events;
  event.data.u64 = tag;
  (void)::epoll_ctl(epoll_fd, operation, fd, &event);
}

driver::Status Hub::Impl::run(int extra_stop_fd) {
  if (epoll_fd < 0) {
    return fail(driver::make_error(driver::ErrorKind::wrong_state, "run", "hub", "listen() first"));
  }
  if (extra_stop_fd >= 0) {
    watch(EPOLL_CTL_ADD, extra_stop_fd, kExtraStopTag, EPOLLIN);
  }
  epoll_event events[64];
  while (!stop_requested.load()) {
    const int count = ::epoll_wait(epoll_fd, events, 64, wait_timeout_ms());
    counters.loop_turns.fetch_add(1, std::memory_order_relaxed);
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
    for (std::vector<std::uint64_t> resumed = std::exchange(resume_parsing, {}); std::uint64_t tag : resumed) {
      take_lines(tag);
    }
    close_idle_clients();
    beat_heart();
    if (!accepting && Clock::now() >= accept_resumes_at) {
      resume_accepting();
    }
  }
  if (extra_stop_fd >= 0) {
    (void)::epoll_ctl(epoll_fd, EPOLL_CTL_DEL, extra_stop_fd, nullptr);
  }
  return ok();
}

int Hub::Impl::wait_timeout_ms() const {
  std::optional<Clock::time_point> due;
  if (!accepting) {
    due = accept_resumes_at;
  }
  if (settings.heartbeat && settings.heartbeat_interval.count() > 0) {
    due = due ? std::min(*due, next_heartbeat) : next_heartbeat;
  }
  if (settings.idle_timeout.count() > 0) {
    for (const auto& [tag, client] : clients) {
      if (client.total_in_flight == 0) {
        const auto expires = client.last_activity + settings.idle_timeout;
        due = due ? std::min(*due, expires) : expires;
      }
    }
  }
  if (!due) {
    return -1;
  }
  const auto left = std::chrono::duration_cast<milliseconds>(*due - Clock::now()).count() + 1;
  return static_cast<int>(std::clamp<long long>(left, 0, 60000));
}

void Hub::Impl::beat_heart() {
  if (!settings.heartbeat || settings.heartbeat_interval.count() <= 0) {
    return;
  }
  if (const auto now = Clock::now(); now >= next_heartbeat) {
    settings.heartbeat();
    next_heartbeat = now + settings.heartbeat_interval;
  }
}

void Hub::Impl::close_idle_clients() {
  if (settings.idle_timeout.count() <= 0) {
    return;
  }
  const auto now = Clock::now();
  std::vector<std::uint64_t> idle;
  for (const auto& [tag, client] : clients) {
    if (client.total_in_flight == 0 && now - client.last_activity >= settings.idle_timeout) {
      idle.push_back(tag);
    }
  }
  for (std::uint64_t tag : idle) {
    counters.closed_idle.fetch_add(1);
    const std::string line =
        format_reply(error_reply(std::string(kUnsolicitedId), "timeout",
                                 "idle for " + std::to_string(settings.idle_timeout.count()) + " ms; closing")) +
        "\n";
    (void)!::send(clients.at(tag).fd, line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    drop_client(tag);
  }
}

void Hub::Impl::pause_accepting(int error) {
  accepting = false;
  accept_resumes_at = Clock::now() + settings.accept_retry;
  watch(EPOLL_CTL_MOD, listen_fd, kListenTag, 0);
  counters.accept_pauses.fetch_add(1);
  if (auto line = accept_warning.admit(std::string("accept: ") + std::strerror(error) + "; not accepting for " +
                                       std::to_string(settings.accept_retry.count()) + " ms")) {
    say_warning(settings.warn, *line);
  }
}

void Hub::Impl::resume_accepting() {
  if (!accepting) {
    accepting = true;
    watch(EPOLL_CTL_MOD, listen_fd, kListenTag, EPOLLIN);
  }
}

void Hub::Impl::accept_clients() {
  while (accepting) {
    const int fd = ::accept4(listen_fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
        pause_accepting(errno);  // the pending connection stays queued until a descriptor is free
      } else if (errno == ECONNABORTED || errno == EINTR || errno == EPROTO) {
        continue;  // that client is gone already; others may be waiting
      }
      return;  // EAGAIN: all taken
    }
    if (clients.size() >= settings.max_clients) {
      const std::string line = format_reply(error_reply(std::string(kUnsolicitedId), "busy",
                                                        "the hub serves at most " +
                                                            std::to_string(settings.max_clients) + " clients")) +
                               "\n";
      (void)!::send(fd, line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      ::close(fd);
      continue;
    }
    const int yes = 1;
    (void)::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
    const std::uint64_t tag = next_tag++;
    HubConnection& client = clients[tag];
    client.fd = fd;
    client.frontend_id = "F" + std::to_string(next_frontend_number++);
    client.last_activity = Clock::now();
    tag_by_frontend[client.frontend_id] = tag;
    counters.clients_accepted.fetch_add(1);
    client.watched_events = EPOLLIN | EPOLLRDHUP;
    watch(EPOLL_CTL_ADD, fd, tag, client.watched_events);
    send_reply(tag, ok_reply(std::string(kUnsolicitedId), "HELLO",
                             {{"femh", client.frontend_id}, {"protocol", std::to_string(kHubProtocolVersion)}}));
  }
}

void Hub::Impl::drop_client(std::uint64_t tag) {
  const auto found = clients.find(tag);
  if (found == clients.end()) {
    return;
  }
  found->second.alive->store(false);
  (void)::epoll_ctl(epoll_fd, EPOLL_CTL_DEL, found->second.fd, nullptr);
  ::close(found->second.fd);
  tag_by_frontend.erase(found->second.frontend_id);
  clients.erase(found);
  resume_accepting();  // a descriptor is free again
}

void Hub::Impl::serve_client(std::uint64_t tag, std::uint32_t events) {
  if ((events & EPOLLOUT) != 0) {
    flush(tag);
  }
  if ((events & (EPOLLIN | EPOLLHUP | EPOLLERR | EPOLLRDHUP)) != 0) {
    read_client(tag);
  }
}

void Hub::Impl::read_client(std::uint64_t tag) {
  char buffer[4096];
  std::size_t budget = settings.read_budget_bytes;
  while (budget > 0) {
    const auto found = clients.find(tag);
    if (found == clients.end() || found->second.reading_paused) {
      return;
    }
    const ssize_t got = ::recv(found->second.fd, buffer, std::min(sizeof buffer, budget), 0);
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
    budget -= static_cast<std::size_t>(got);
    // Only bytes of a request count as activity: blank lines (newlines, spaces) would keep an idle
    // client's descriptor forever (issue 27).
    const std::string_view chunk(buffer, static_cast<std::size_t>(got));
    if (chunk.find_first_not_of(" \t\r\n") != std::string_view::npos) found->second.last_activity = Clock::now();
    found->second.input.append(buffer, static_cast<std::size_t>(got));
    take_lines(tag);
  }
}

void Hub::Impl::take_lines(std::uint64_t tag) {
  for (;;) {
    const auto found = clients.find(tag);
    if (found == clients.end() || found->second.reading_paused) {
      return;  // paused: the lines wait in `input` until the replies drain
    }
    HubConnection& client = found->second;
    const std::size_t end = client.input.find('\n');
    if (end == std::string::npos) {
      if (client.input.size() > kMaxRequestLineLength) {
        if (!client.discarding_long_line) {
          send_reply(tag, error_reply(std::string(kUnknownId), "bad_request",
                                      "request line longer than " + std::to_string(kMaxRequestLineLength) +
                                          " bytes"));
        }
        if (const auto still = clients.find(tag); still != clients.end()) {
          still->second.discarding_long_line = true;
          still->second.input.clear();
        }
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

void Hub::Impl::send_reply(std::uint64_t tag, const HubReply& reply) {
  const auto found = clients.find(tag);
  if (found == clients.end()) {
    return;
  }
  HubConnection& client = found->second;
  client.output.append(format_reply(reply));
  client.output.append("\n");
  const std::uint64_t waiting = client.output.pending();
  if (waiting > counters.peak_output_bytes.load(std::memory_order_relaxed)) {
    counters.peak_output_bytes.store(waiting, std::memory_order_relaxed);
  }
  if (waiting > settings.max_output_bytes) {
    counters.closed_slow.fetch_add(1);
    drop_client(tag);
    return;
  }
  flush(tag);
}

void Hub::Impl::flush(std::uint64_t tag) {
  const auto found = clients.find(tag);
  if (found == clients.end()) {
    return;
  }
  HubConnection& client = found->second;
  while (!client.output.empty()) {
    const ssize_t sent = ::send(client.fd, client.output.data(), client.output.pending(), MSG_NOSIGNAL);
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
    client.output.consume(static_cast<std::size_t>(sent));
  }
  const std::size_t waiting = client.output.pending();
  if (!client.reading_paused && waiting > settings.pause_reading_above) {
    client.reading_paused = true;
  } else if (client.reading_paused && waiting <= settings.pause_reading_above / 2) {
    client.reading_paused = false;
    resume_parsing.push_back(tag);  // lines already read wait in `input`
  }
  const std::uint32_t wanted = (client.reading_paused ? 0u : std::uint32_t{EPOLLIN | EPOLLRDHUP}) |
                               (waiting > 0 ? std::uint32_t{EPOLLOUT} : 0u);
  if (wanted != client.watched_events) {
    watch(EPOLL_CTL_MOD, client.fd, tag, wanted);
    client.watched_events = wanted;
  }
}

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

HubCounters Hub::counters() const {
  const AtomicCounters& c = impl_->counters;
  return HubCounters{c.clients_accepted.load(), c.requests.load(),   c.answered_from_cache.load(),
                     c.forwarded.load(),        c.errors.load(),     c.closed_idle.load(),
                     c.closed_slow.load(),      c.accept_pauses.load(), c.loop_turns.load(),
                     c.peak_output_bytes.load()};
}

}  // namespace ldoem::hub
