#include "ldoem/control_socket/control_server.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "ldoem/control_socket/control_protocol.hpp"

namespace ldoem::control_socket {

struct ControlServer::Client {
  base::UniqueFd fd;
  int number = 0;
  LineAssembler lines;
  std::string output;  // bytes not yet written
  bool closing = false;  // write what is queued, then close (too many clients, queue overflow)
  bool greeted = false;  // counted as a client (CONNECTION events)
  bool waiting = false;  // a deferred reply is outstanding: lines wait in `held`
  std::deque<AssembledLine> held;  // at most one read's worth: the client is not read while waiting
};

namespace {

// Only the daemon's user may connect (the issue: not accessible to other users).
constexpr mode_t kSocketMode = 0600;
constexpr std::size_t kReadChunkBytes = 4096;
// The listen backlog: clients beyond it wait in connect() until the loop accepts them.
constexpr int kListenBacklog = 128;

io::IoResult<sockaddr_un> unix_address(const std::string& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof(address.sun_path)) {
    return io::io_failure({"control", path, ENAMETOOLONG, "the socket path must be 1..107 bytes"});
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  return address;
}

// A socket file left behind by a daemon that died is replaced; a live socket or any other file
// is not touched.
io::IoStatus clear_stale_socket(const std::string& path, const sockaddr_un& address) {
  struct stat info {};
  if (lstat(path.c_str(), &info) != 0) return io::Done{};  // nothing there
  if (!S_ISSOCK(info.st_mode)) return io::io_failure({"control", path, EEXIST, "exists and is not a socket"});
  base::UniqueFd probe(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (probe.get() < 0) return io::io_failure(io::last_system_error("socket", path));
  if (connect(probe.get(), reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0) {
    return io::io_failure({"control", path, EADDRINUSE, "another daemon is listening on it"});
  }
  if (unlink(path.c_str()) != 0) return io::io_failure(io::last_system_error("unlink", path));
  return io::Done{};
}

}  // namespace

ControlServer::ControlServer(io::EventLoop& loop, std::string path, std::string greeting, LineHandler handler,
                             ServerLimits limits)
    : loop_(loop), path_(std::move(path)), greeting_(std::move(greeting)), handler_(std::move(handler)), limits_(limits) {}

io::IoResult<std::unique_ptr<ControlServer>> ControlServer::open(io::EventLoop& loop, std::string path, std::string greeting,
                                                                 LineHandler handler, ServerLimits limits) {
  auto address = unix_address(path);
  if (!address) return io::io_failure(address.error());
  if (auto cleared = clear_stale_socket(path, *address); !cleared) return io::io_failure(cleared.error());
  std::unique_ptr<ControlServer> server(
      new ControlServer(loop, std::move(path), std::move(greeting), std::move(handler), limits));
  server->listen_fd_.reset(socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (server->listen_fd_.get() < 0) return io::io_failure(io::last_system_error("socket", server->path_));
  // The umask decides the mode bind() creates the file with: never a moment with wider access.
  const mode_t previous_umask = umask(static_cast<mode_t>(~kSocketMode & 0777));
  const int bound = bind(server->listen_fd_.get(), reinterpret_cast<const sockaddr*>(&*address), sizeof(*address));
  const int bind_errno = errno;
  umask(previous_umask);
  if (bound != 0) {
    errno = bind_errno;
    return io::io_failure(io::last_system_error("bind", server->path_));
  }
  if (chmod(server->path_.c_str(), kSocketMode) != 0) return io::io_failure(io::last_system_error("chmod", server->path_));
  if (listen(server->listen_fd_.get(), kListenBacklog) != 0) return io::io_failure(io::last_system_error("listen", server->path_));
  ControlServer* self = server.get();
  if (auto watched = loop.watch(server->listen_fd_.get(), io::Interest::readable,
                                [self](io::Readiness) { self->accept_clients(); });
      !watched) {
    return io::io_failure(watched.error());
  }
  return server;
}

ControlServer::~ControlServer() {
  if (resting_) loop_.cancel_timer(resume_timer_);
  for (const auto& client : clients_) loop_.unwatch(client->fd.get());
  if (listen_fd_.get() >= 0) {
    if (!resting_) loop_.unwatch(listen_fd_.get());
    unlink(path_.c_str());
  }
}

void ControlServer::accept_clients() {
  for (;;) {
    const int fd = accept4(listen_fd_.get(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      const int error = errno;
      if (error == EMFILE || error == ENFILE || error == ENOBUFS || error == ENOMEM) rest(error);
      return;  // EAGAIN, or a client that vanished: nothing to do
    }
    auto client = std::make_unique<Client>(Client{base::UniqueFd(fd), next_client_number_++,
                                                  LineAssembler(limits_.max_line_bytes), {}, false, false, false, {}});
    Client& added = *client;
    clients_.push_back(std::move(client));
    if (clients_.size() > limits_.max_clients) {
      // Told why, then closed once the line is out.
      queue(added, error_line(kGenericError, "too many control clients (limit " +
                                                 std::to_string(limits_.max_clients) + ")"));
      added.closing = true;
    } else {
      queue(added, greeting_);
      added.greeted = true;
      if (observer_) observer_(true, added.number);
    }
    if (!loop_.watch(fd, io::Interest::readable | io::Interest::writable,
                     [this, fd](io::Readiness readiness) { on_client(fd, readiness); })) {
      drop(fd);
    }
  }
}

// Issue 27 D3: out of descriptors (or kernel memory), the pending connection stays pending and
// the socket stays readable: a level-triggered loop would call accept4() again at once, forever.
// The listener rests as the TCP listener does, and says so at most every 10 s.
void ControlServer::rest(int error) {
  ++listener_rests_;
  const auto now = std::chrono::steady_clock::now();
  if (!warned_once_ || now - last_warning_ >= kRestWarningPeriod) {
    std::string line = "control: accept " + path_ + ": " + std::strerror(error) + "; not accepting for " +
                       std::to_string(kListenerRest.count()) + " ms";
    if (rests_unsaid_ > 0) line += " (" + std::to_string(rests_unsaid_) + " more since the last report)";
    if (warn_) warn_(line);
    warned_once_ = true;
    last_warning_ = now;
    rests_unsaid_ = 0;
  } else {
    ++rests_unsaid_;
  }
  if (resting_) return;
  resting_ = true;
  loop_.unwatch(listen_fd_.get());
  resume_timer_ = loop_.add_timer_after(kListenerRest, [this] {
    resting_ = false;
    if (auto watched = loop_.watch(listen_fd_.get(), io::Interest::readable, [this](io::Readiness) { accept_clients(); });
        !watched && warn_) {
      warn_("control: " + watched.error().message());
    }
  });
}

void ControlServer::queue(Client& client, const std::string& line) {
  if (client.closing) return;
  if (client.output.size() + line.size() + 1 > limits_.max_queued_bytes) {
    client.closing = true;  // it does not read: dropped, its queue with it
    client.output.clear();
    ++clients_dropped_;
    return;
  }
  client.output += line;
  client.output += '\n';
}

void ControlServer::flush(Client& client) {
  while (!client.output.empty()) {
    const ssize_t written = send(client.fd.get(), client.output.data(), client.output.size(), MSG_NOSIGNAL);
    if (written <= 0) return;  // EAGAIN (retried when writable) or an error (seen as hang-up)
    client.output.erase(0, static_cast<std::size_t>(written));
  }
}

void ControlServer::on_client(int fd, io::Readiness readiness) {
  auto found = std::find_if(clients_.begin(), clients_.end(), [fd](const auto& c) { return c->fd.get() == fd; });
  if (found == clients_.end()) return;
  Client& client = **found;
  const int number = client.number;
  bool peer_gone = readiness.hang_up || readiness.error;
  if (readiness.readable && !client.closing && !client.waiting) {
    char buffer[kReadChunkBytes];
    const ssize_t got = recv(fd, buffer, sizeof(buffer), 0);
    if (got == 0 || (got < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      peer_gone = true;
    } else if (got > 0) {
      std::vector<AssembledLine> lines;
      client.lines.feed(std::string_view(buffer, static_cast<std::size_t>(got)), lines);
      for (AssembledLine& line : lines) client.held.push_back(std::move(line));
      if (!serve(number)) return;
    }
  }
  Client* still = find(number);
  if (still == nullptr) return;
  flush(*still);
  if (peer_gone || (still->closing && still->output.empty())) {
    drop(fd);
    return;
  }
  update_interest(*still);
}

bool ControlServer::serve(int number) {
  for (Client* client = find(number); client != nullptr && !client->waiting && !client->held.empty();
       client = find(number)) {
    const AssembledLine line = std::move(client->held.front());
    client->held.pop_front();
    if (line.too_long) {
      queue(*client, error_line(kGenericError, "line longer than " + std::to_string(limits_.max_line_bytes) +
                                                   " bytes: skipped"));
      continue;
    }
    if (line.text.empty()) continue;
    serving_ = number;
    deferred_ = false;
    const std::string reply = handler_(line.text);
    serving_ = 0;
    client = find(number);  // the handler's events may have dropped it (a full queue)
    if (client == nullptr) return false;
    if (deferred_) {
      client->waiting = true;
    } else {
      queue(*client, reply);
    }
  }
  return find(number) != nullptr;
}

void ControlServer::update_interest(Client& client) {
  // Wait for writability only while something is queued (level-triggered epoll would spin); read
  // nothing while a deferred reply is outstanding (hang-ups are reported all the same).
  std::uint32_t bits = 0;
  if (!client.closing && !client.waiting) bits |= static_cast<std::uint32_t>(io::Interest::readable);
  if (!client.output.empty() || client.closing) bits |= static_cast<std::uint32_t>(io::Interest::writable);
  (void)loop_.change_interest(client.fd.get(), static_cast<io::Interest>(bits));
}

ControlServer::Client* ControlServer::find(int number) {
  auto found = std::find_if(clients_.begin(), clients_.end(), [number](const auto& c) { return c->number == number; });
  return found == clients_.end() ? nullptr : found->get();
}

ControlServer::Ticket ControlServer::defer() {
  deferred_ = true;
  return serving_;
}

void ControlServer::complete(Ticket ticket, const std::string& line) {
  Client* client = find(ticket);
  if (client == nullptr) return;
  client->waiting = false;
  queue(*client, line);
  if (!serve(ticket)) return;
  client = find(ticket);
  flush(*client);
  if (client->closing && client->output.empty()) {
    drop(client->fd.get());
    return;
  }
  update_interest(*client);
}

void ControlServer::broadcast(const std::string& line) {
  std::vector<int> overflowed;
  for (const auto& client : clients_) {
    if (client->closing) continue;
    queue(*client, line);
    if (client->closing) {
      overflowed.push_back(client->fd.get());
      continue;
    }
    flush(*client);
    if (!client->output.empty()) {
      (void)loop_.change_interest(client->fd.get(), io::Interest::readable | io::Interest::writable);
    }
  }
  for (int fd : overflowed) drop(fd);
}

void ControlServer::drop(int fd) {
  auto found = std::find_if(clients_.begin(), clients_.end(), [fd](const auto& c) { return c->fd.get() == fd; });
  if (found == clients_.end()) return;
  loop_.unwatch(fd);
  const bool greeted = (*found)->greeted;
  const int number = (*found)->number;
  clients_.erase(found);
  if (greeted && observer_) observer_(false, number);
}

}  // namespace ldoem::control_socket
