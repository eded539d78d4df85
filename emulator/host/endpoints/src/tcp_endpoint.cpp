#include "ldoem/endpoints/tcp_endpoint.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <string>
#include <variant>
#include <vector>

#include "ldoem/endpoints/read_budget.hpp"
#include "ldoem/protocol/wire_corruption.hpp"

namespace ldoem::endpoints {

std::optional<OpenFailure> TcpHostEndpoint::open(EndpointContext& context) {
  context_ = &context;
  auto listener = io::TcpListener::listen(port_, address_);
  if (!listener) {
    return OpenFailure{true, listener.error().message()};
  }
  listener_.emplace(std::move(*listener));
  if (auto failure = watch_readable(context, listener_->fd(), [this](io::Readiness) { on_listener_ready(); })) {
    return failure;
  }
  context.out << "tcp " << listener_->address() << ':' << listener_->port() << '\n';
  return std::nullopt;
}

std::optional<std::uint16_t> TcpHostEndpoint::port() const {
  if (!listener_) return std::nullopt;
  return listener_->port();
}

bool TcpHostEndpoint::busy(ConnectionId connection) const {
  const auto client = clients_.find(connection.index);
  return client != clients_.end() && !client->second.output.empty();
}

// At most kAcceptBudget connections per loop round: between rounds the loop serves the clients,
// so a connect flood does not starve them.
void TcpHostEndpoint::on_listener_ready() {
  ++context_->activity;
  for (std::size_t round_accepts = 0; round_accepts < kAcceptBudget; ++round_accepts) {
    auto accepted = listener_->accept();
    if (!accepted) {
      const int error = accepted.error().error_number;
      if (error == EMFILE || error == ENFILE || error == ENOBUFS || error == ENOMEM) {
        rest_listener(accepted.error().message());
      } else {
        context_->logger.log(LogLevel::warn, accepted.error().message());
      }
      return;
    }
    if (!accepted->has_value()) {
      return;
    }
    if (clients_.size() >= limits_.max_tcp_clients) free_places_of_gone_hosts();
    if (clients_.size() >= limits_.max_tcp_clients) {
      // Accepted and closed at once (leaving scope): the host protocol has no "busy" reply.
      ++context_->counters.tcp_refused;
      if (auto line = refused_warning_.admit("tcp: --max-clients " + std::to_string(limits_.max_tcp_clients) +
                                             " reached; closing the new connection from " + (*accepted)->peer())) {
        context_->logger.log(LogLevel::warn, *line);
      }
      continue;
    }
    const auto taken = indices_.take([this](std::uint32_t index) { return clients_.contains(index); });
    if (!taken) {
      // Every connection number is in use: the new connection is closed, the others go on.
      context_->logger.log(LogLevel::warn, "tcp: every connection number is in use; closing the connection from " +
                                               (*accepted)->peer());
      continue;
    }
    const std::uint32_t index = *taken;
    const int fd = (*accepted)->fd();
    const auto now = std::chrono::steady_clock::now();
    context_->logger.log(LogLevel::info, "tcp#" + std::to_string(index) + " connected from " + (*accepted)->peer());
    clients_.emplace(index, Client{std::move(**accepted), protocol::TcpDeframer(), OutputQueue(), {}, false, {}, now,
                                   false, std::nullopt, std::nullopt});
    ++context_->counters.tcp_connections;
    context_->sink.on_connection_opened(ConnectionId{protocol::Transport::tcp, index}, clients_.at(index).connection.peer());
    if (auto watched = context_->loop.watch(fd, io::Interest::readable,
                                            [this, index](io::Readiness r) { on_client_ready(index, r); });
        !watched) {
      drop(index, watched.error().message());
      continue;
    }
    if (limits_.silent_timeout.count() > 0) {
      arm_quiet_timer(index, now + limits_.silent_timeout);
    } else if (limits_.idle_timeout.count() > 0) {
      arm_quiet_timer(index, now + limits_.idle_timeout);
    }
  }
}

// At the limit, a place held by a host that has already gone (its EOF or reset not read yet,
// e.g. a flood of connections reset at once) is freed before the new host is judged, through
// the usual read path (which drops it). One peek per connection, only when every place is taken.
void TcpHostEndpoint::free_places_of_gone_hosts() {
  std::vector<std::uint32_t> gone;
  for (const auto& [index, client] : clients_) {
    if (client.connection.peer_gone()) gone.push_back(index);
  }
  for (const std::uint32_t index : gone) on_client_ready(index, io::Readiness{true, false, true, false});
}

// After bytes from the host: a frame left incomplete must be finished within the inter-byte
// timeout (spec 6), else its start is dropped instead of being joined to whatever comes next.
void TcpHostEndpoint::after_receive(std::uint32_t index) {
  const auto client = clients_.find(index);
  if (client == clients_.end()) return;
  Client& c = client->second;
  c.last_received = std::chrono::steady_clock::now();
  if (c.inter_byte_timer) {
    context_->loop.cancel_timer(*c.inter_byte_timer);
    c.inter_byte_timer.reset();
  }
  if (limits_.inter_byte_timeout.count() > 0 && c.deframer.in_frame()) {
    c.inter_byte_timer = context_->loop.add_timer_after(limits_.inter_byte_timeout,
                                                         [this, index] { on_inter_byte_timeout(index); });
  }
}

void TcpHostEndpoint::on_inter_byte_timeout(std::uint32_t index) {
  const auto client = clients_.find(index);
  if (client == clients_.end()) return;
  client->second.inter_byte_timer.reset();
  if (!client->second.deframer.in_frame()) return;
  if (client->second.stalled) {  // D11 tcp_stall: we are the ones not reading; wait for the rest
    after_receive(index);
    return;
  }
  client->second.deframer.reset();
  ++context_->activity;
  context_->logger.log(LogLevel::info, "tcp#" + std::to_string(index) + ": frame incomplete after " +
                                           std::to_string(limits_.inter_byte_timeout.count()) + " ms; dropped (spec 6)");
  context_->sink.on_framing_error(ConnectionId{protocol::Transport::tcp, index},
                                  protocol::FramingError{protocol::DecodeError::timeout, 0});
}

void TcpHostEndpoint::arm_quiet_timer(std::uint32_t index, std::chrono::steady_clock::time_point at) {
  const auto client = clients_.find(index);
  if (client == clients_.end()) return;
  client->second.quiet_timer = context_->loop.add_timer_at(at, [this, index] { on_quiet_timer(index); });
}

// One timer per connection, checked lazily: bytes that arrived since it was armed move it on
// instead of re-arming it for every read.
void TcpHostEndpoint::on_quiet_timer(std::uint32_t index) {
  const auto client = clients_.find(index);
  if (client == clients_.end()) return;
  Client& c = client->second;
  c.quiet_timer.reset();
  if (c.stalled) {  // D11 tcp_stall: the host's bytes wait unread; its quiet time starts again
    c.last_received = std::chrono::steady_clock::now();
    arm_quiet_timer(index, c.last_received + std::max(limits_.silent_timeout, limits_.idle_timeout));
    return;
  }
  if (!c.spoke && limits_.silent_timeout.count() > 0) {
    ++context_->counters.tcp_dropped_quiet;
    drop(index, "no telegram within " + std::to_string(limits_.silent_timeout.count()) + " ms of connecting");
    return;
  }
  if (limits_.idle_timeout.count() <= 0) return;
  const auto due = c.last_received + limits_.idle_timeout;
  if (std::chrono::steady_clock::now() >= due) {
    ++context_->counters.tcp_dropped_quiet;
    drop(index, "idle for " + std::to_string(limits_.idle_timeout.count()) + " ms");
    return;
  }
  arm_quiet_timer(index, due);
}

// Out of descriptors, the pending connection stays queued and the listener stays readable: a
// level-triggered loop would spin on it (issue 11: 1.9 million warnings in 3 s). The listener is
// unwatched for kListenerRest, or until a client leaves, and the warning is said at most once
// per kWarnPeriod with the count of the ones held back.
void TcpHostEndpoint::rest_listener(const std::string& why) {
  ++listener_rests_;
  if (auto line = rest_warning_.admit(why + "; not accepting for " + std::to_string(kListenerRest.count()) + " ms")) {
    context_->logger.log(LogLevel::warn, *line);
  }
  if (listener_resting_) return;
  listener_resting_ = true;
  context_->loop.unwatch(listener_->fd());
  resume_timer_ = context_->loop.add_timer_after(kListenerRest, [this] { resume_listener(); });
}

void TcpHostEndpoint::resume_listener() {
  if (!listener_resting_ || !listener_ || dark_) return;
  listener_resting_ = false;
  context_->loop.cancel_timer(resume_timer_);
  if (auto watched = context_->loop.watch(listener_->fd(), io::Interest::readable, [this](io::Readiness) { on_listener_ready(); });
      !watched) {
    context_->logger.log(LogLevel::warn, watched.error().message());
  }
}

void TcpHostEndpoint::on_client_ready(std::uint32_t index, io::Readiness readiness) {
  ++context_->activity;
  const ConnectionId connection{protocol::Transport::tcp, index};
  if (fault_hook_ != nullptr) {
    const auto client = clients_.find(index);
    if (client != clients_.end() && stalled(index, client->second)) return;  // D11 tcp_stall: nothing is read
  }
  if (readiness.writable) {
    flush(index);
  }
  std::size_t budget = kReadBudgetBytes;
  while (budget > 0) {
    const auto client = clients_.find(index);
    if (client == clients_.end()) {
      return;  // dropped while serving its own telegrams
    }
    auto received = client->second.connection.receive(budget);
    if (!received) {
      drop(index, received.error().message());
      return;
    }
    if (received->bytes.empty()) {
      if (received->peer_closed) {
        drop(index, "peer closed");
      }
      break;
    }
    budget -= std::min(budget, received->bytes.size());
    const auto events = client->second.deframer.feed(received->bytes);
    after_receive(index);
    for (const protocol::DeframerEvent& event : events) {
      const auto still = clients_.find(index);
      if (still == clients_.end()) {
        return;
      }
      if (const auto* telegram = std::get_if<protocol::Telegram>(&event)) {
        if (!still->second.spoke) {
          still->second.spoke = true;
          // Silent no more: from now on only the idle timeout (if any) applies.
          if (still->second.quiet_timer) context_->loop.cancel_timer(*still->second.quiet_timer);
          still->second.quiet_timer.reset();
          if (limits_.idle_timeout.count() > 0) arm_quiet_timer(index, still->second.last_received + limits_.idle_timeout);
        }
        context_->sink.on_telegram(connection, telegram->payload);
      } else {
        context_->sink.on_framing_error(connection, std::get<protocol::FramingError>(event));
      }
    }
    if (received->peer_closed) {
      drop(index, "peer closed");
      return;
    }
    if (fault_hook_ != nullptr) {
      if (dark_) return;  // D11 power_cycle started by a telegram just read: nothing more is read
      // D11 tcp_stall started by a telegram just read: nothing more is read from now on.
      const auto still = clients_.find(index);
      if (still != clients_.end() && stalled(index, still->second)) return;
    }
  }
}

void TcpHostEndpoint::send(ConnectionId to, protocol::ByteView payload) {
  const auto client = clients_.find(to.index);
  if (client == clients_.end() || dark_) {
    return;  // the connection closed before its reply was ready, or the device is off (D11)
  }
  protocol::Bytes frame = protocol::encode_tcp_frame(payload);
  if (fault_hook_ != nullptr) {
    // D11 corrupt_checksum, garbage: the frame as a faulty wire delivers it.
    TelegramFaults faults = fault_hook_->on_outgoing_telegram(to, payload, context_->scheduler.now());
    if (faults.corrupt_checksum) protocol::corrupt_tcp_checksum(frame);
    if (!faults.garbage_before.empty()) {
      faults.garbage_before.insert(faults.garbage_before.end(), frame.begin(), frame.end());
      frame = std::move(faults.garbage_before);
    }
  }
  if (!client->second.output.push(frame)) {
    ++context_->counters.tcp_dropped_slow;
    drop(to.index, "output queue over " + std::to_string(client->second.output.max_bytes()) +
                       " bytes (host does not read)");
    return;
  }
  flush(to.index);
}

void TcpHostEndpoint::flush(std::uint32_t index) {
  const auto client = clients_.find(index);
  if (client == clients_.end() || dark_) return;
  OutputQueue& output = client->second.output;
  if (fault_hook_ != nullptr && (stalled(index, client->second) || paced(index, client->second))) return;
  while (!output.empty()) {
    // One send per telegram while the kernel has room (D10, spec 6: no gap inside a frame).
    auto sent = client->second.connection.send(output.front());
    if (!sent) {
      drop(index, sent.error().message());
      return;
    }
    if (*sent == 0) break;
    output.consume(*sent);
  }
  const io::Interest interest = output.empty() ? io::Interest::readable : io::Interest::readable | io::Interest::writable;
  (void)context_->loop.change_interest(client->second.connection.fd(), interest);
}

void TcpHostEndpoint::drop(std::uint32_t index, std::string_view why, bool reset) {
  const auto client = clients_.find(index);
  if (client == clients_.end()) return;
  context_->logger.log(LogLevel::info, "tcp#" + std::to_string(index) + (reset ? " reset: " : " closed: ") + std::string(why));
  if (reset) {
    if (auto abortive = client->second.connection.reset_on_close(); !abortive) {
      context_->logger.log(LogLevel::warn, abortive.error().message() + "; closed with a FIN instead");
    }
  }
  context_->loop.unwatch(client->second.connection.fd());
  if (client->second.fault_resume) context_->scheduler.cancel(*client->second.fault_resume);
  // Its timers go with it: the index may be given to a new connection.
  if (client->second.inter_byte_timer) context_->loop.cancel_timer(*client->second.inter_byte_timer);
  if (client->second.quiet_timer) context_->loop.cancel_timer(*client->second.quiet_timer);
  clients_.erase(client);
  resume_listener();  // a descriptor is free again
  context_->sink.on_connection_closed(ConnectionId{protocol::Transport::tcp, index});
}

void TcpHostEndpoint::disconnect(ConnectionId connection) { drop(connection.index, "by a fault (D11)", true); }

void TcpHostEndpoint::close() {
  std::vector<std::uint32_t> indices;  // flush() may drop a client: not while iterating
  for (const auto& [index, client] : clients_) indices.push_back(index);
  for (const std::uint32_t index : indices) flush(index);
}

}  // namespace ldoem::endpoints
