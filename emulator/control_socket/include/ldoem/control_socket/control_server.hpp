// The UNIX stream socket of `ldoem-emud --control PATH`: mode 0600 (only the daemon's user may
// connect), a greeting to each client, one reply line per request line, event lines to every
// client. Everything is bounded: line length, number of clients, bytes queued per client. A
// client over a bound gets an error object; one that stops reading while its queue is full is
// disconnected. Runs on the daemon's event loop; no threads.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ldoem/control_socket/line_assembler.hpp"
#include "ldoem/base/unique_fd.hpp"
#include "ldoem/io/event_loop.hpp"

namespace ldoem::control_socket {

struct ServerLimits {
  std::size_t max_line_bytes = 64 * 1024;
  std::size_t max_clients = 128;
  std::size_t max_queued_bytes = 1024 * 1024;  // per client
};

class ControlServer {
 public:
  using LineHandler = std::function<std::string(std::string_view line)>;
  // Told when a client connects (true) or goes (false), for the CONNECTION events.
  using ClientObserver = std::function<void(bool opened, int client_number)>;

  // Creates the socket at `path` (a stale socket left by a dead daemon is replaced; a live one
  // or any other file is an error), mode 0600.
  static io::IoResult<std::unique_ptr<ControlServer>> open(io::EventLoop& loop, std::string path, std::string greeting,
                                                           LineHandler handler, ServerLimits limits = {});
  ~ControlServer();  // closes every client and removes the socket file
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  void set_client_observer(ClientObserver observer) { observer_ = std::move(observer); }
  // Where the server's own warnings go (descriptors running out), one line each, no newline.
  void set_warning_sink(std::function<void(const std::string&)> warn) { warn_ = std::move(warn); }
  // Times accept() failed for want of descriptors or memory and the listener rested.
  std::uint64_t listener_rests() const { return listener_rests_; }
  // One line (no newline) to every client.
  void broadcast(const std::string& line);

  // Issue 27: a request whose work runs off the loop (add-object's mesh import). The line handler
  // calls defer() while it handles a line and returns anything: that line's reply is the one
  // given to complete(ticket, ...) later, on the loop's thread. Until then the client's further
  // lines wait (replies stay in request order) and it is not read from; the other clients are
  // served. complete() for a client that has gone does nothing.
  using Ticket = int;
  Ticket defer();
  void complete(Ticket ticket, const std::string& line);
  std::size_t client_count() const { return clients_.size(); }
  std::uint64_t clients_dropped() const { return clients_dropped_; }
  const std::string& path() const { return path_; }

 private:
  struct Client;
  ControlServer(io::EventLoop& loop, std::string path, std::string greeting, LineHandler handler, ServerLimits limits);
  void accept_clients();
  void on_client(int fd, io::Readiness readiness);
  // Handles the client's held lines until one is deferred; false when the client was dropped.
  bool serve(int number);
  void update_interest(Client& client);
  Client* find(int number);
  void queue(Client& client, const std::string& line);
  void flush(Client& client);
  void drop(int fd);
  void rest(int error);

  // Out of descriptors the listener is not watched this long (as the TCP listener, issue 11).
  static constexpr std::chrono::milliseconds kListenerRest{100};
  static constexpr std::chrono::seconds kRestWarningPeriod{10};

  io::EventLoop& loop_;
  std::string path_;
  std::string greeting_;
  LineHandler handler_;
  ServerLimits limits_;
  ClientObserver observer_;
  base::UniqueFd listen_fd_;
  std::vector<std::unique_ptr<Client>> clients_;
  int next_client_number_ = 1;
  int serving_ = 0;        // the client whose line the handler is handling (0: none)
  bool deferred_ = false;  // the handler called defer()
  std::uint64_t clients_dropped_ = 0;
  std::function<void(const std::string&)> warn_;
  bool resting_ = false;
  io::EventLoop::TimerId resume_timer_ = 0;
  std::uint64_t listener_rests_ = 0;
  bool warned_once_ = false;
  std::chrono::steady_clock::time_point last_warning_{};
  std::uint64_t rests_unsaid_ = 0;
};

}  // namespace ldoem::control_socket
