// D11 tcp_stall and bandwidth inside the TCP endpoint (wire_fault_hook.hpp). Only reached when
// the daemon set a fault hook; otherwise tcp_endpoint.cpp never calls these. And power_cycle
// (set_power, docs/decisions-local.md L-faults-5), called only by the fault machinery.
#include <algorithm>

#include "ldoem/endpoints/tcp_endpoint.hpp"

namespace ldoem::endpoints {
namespace {

// bandwidth: bytes leave in pieces of 1/100 s of the rate (at least one byte), each piece when
// its last byte would be on a wire of that rate.
constexpr std::uint32_t kPacedPiecesPerSecond = 100;

SimTime wire_time(std::size_t bytes, std::uint32_t bytes_per_s) {
  const std::uint64_t nanoseconds = (static_cast<std::uint64_t>(bytes) * 1'000'000'000ULL + bytes_per_s - 1) / bytes_per_s;
  return SimTime(static_cast<SimTime::rep>(nanoseconds));
}

}  // namespace

// tcp_stall: neither read nor write. The descriptor is unwatched (a level-triggered loop would
// spin on a socket nobody reads) until the hook's time, then asked again.
bool TcpHostEndpoint::stalled(std::uint32_t index, Client& client) {
  if (client.stalled) return true;
  const SimTime now = context_->scheduler.now();
  const auto until = fault_hook_->stalled_until(ConnectionId{protocol::Transport::tcp, index}, now);
  if (!until || *until <= now) return false;
  if (client.fault_resume) context_->scheduler.cancel(*client.fault_resume);  // a paced piece waits with the rest
  client.stalled = true;
  context_->loop.unwatch(client.connection.fd());
  client.fault_resume = context_->scheduler.add(*until, [this, index](SimTime) { resume_after_fault(index); });
  return true;
}

// bandwidth: one piece at a time, from a deadline; the socket is not watched for writing meanwhile.
bool TcpHostEndpoint::paced(std::uint32_t index, Client& client) {
  if (client.fault_resume) return true;  // the next piece is already due at its time
  if (client.output.empty()) return false;
  const SimTime now = context_->scheduler.now();
  const auto rate = fault_hook_->bytes_per_second(ConnectionId{protocol::Transport::tcp, index}, now);
  if (!rate || *rate == 0) return false;
  const std::size_t piece =
      std::min(client.output.front().size(), std::max<std::size_t>(1, *rate / kPacedPiecesPerSecond));
  const SimTime due = std::max(now, client.wire_free_at) + wire_time(piece, *rate);
  (void)context_->loop.change_interest(client.connection.fd(), io::Interest::readable);
  client.fault_resume = context_->scheduler.add(due, [this, index, piece](SimTime at) {
    const auto found = clients_.find(index);
    if (found == clients_.end()) return;
    Client& paced_client = found->second;
    paced_client.fault_resume.reset();
    paced_client.wire_free_at = at;
    auto sent = paced_client.connection.send(paced_client.output.front().first(piece));
    if (!sent) {
      drop(index, sent.error().message());
      return;
    }
    paced_client.output.consume(*sent);
    flush(index);
  });
  return true;
}

void TcpHostEndpoint::resume_after_fault(std::uint32_t index) {
  const auto found = clients_.find(index);
  if (found == clients_.end()) return;
  Client& client = found->second;
  client.fault_resume.reset();
  if (client.stalled) {
    client.stalled = false;
    if (auto watched = context_->loop.watch(client.connection.fd(), io::Interest::readable,
                                            [this, index](io::Readiness r) { on_client_ready(index, r); });
        !watched) {
      drop(index, watched.error().message());
      return;
    }
  }
  flush(index);
}

void TcpHostEndpoint::set_power(DevicePower power) {
  switch (power) {
    case DevicePower::off: go_dark(); return;
    case DevicePower::booting: reset_dark_connections(); return;
    case DevicePower::on: wake(); return;
  }
}

// Off: the listener stops (its port stays ours; a connect() is refused by the kernel), and each
// connection is left exactly as it is on the wire: nothing read, nothing written, no timer of
// ours ends it, what was queued for it is gone with the device's memory.
void TcpHostEndpoint::go_dark() {
  if (dark_) return;
  dark_ = true;
  if (listener_) {
    if (listener_resting_) context_->loop.cancel_timer(resume_timer_);
    listener_resting_ = false;
    context_->loop.unwatch(listener_->fd());
    if (auto stopped = listener_->stop_listening(); !stopped) {
      context_->logger.log(LogLevel::warn, stopped.error().message() + ": new connections are still completed while off");
    }
  }
  for (auto& [index, client] : clients_) {
    context_->loop.unwatch(client.connection.fd());
    if (client.fault_resume) context_->scheduler.cancel(*client.fault_resume);
    if (client.inter_byte_timer) context_->loop.cancel_timer(*client.inter_byte_timer);
    if (client.quiet_timer) context_->loop.cancel_timer(*client.quiet_timer);
    client.fault_resume.reset();
    client.inter_byte_timer.reset();
    client.quiet_timer.reset();
    client.stalled = false;
    client.output.clear();
    client.deframer.reset();
  }
}

// Power back: the new firmware knows none of the old connections; each is reset (RST), as the
// device's stack answers the host's next segment. The listener waits for the end of the boot.
void TcpHostEndpoint::reset_dark_connections() {
  std::vector<std::uint32_t> indices;
  for (const auto& [index, client] : clients_) indices.push_back(index);
  for (const std::uint32_t index : indices) drop(index, "the device was switched off (D11 power_cycle)", true);
}

void TcpHostEndpoint::wake() {
  if (!dark_) return;
  reset_dark_connections();  // booting skipped (boot_s 0): the same reset first
  dark_ = false;
  if (!listener_) return;
  if (auto resumed = listener_->listen_again(); !resumed) {
    context_->logger.log(LogLevel::error, resumed.error().message() + ": the TCP port stays closed after the power cycle");
    return;
  }
  if (auto watched = context_->loop.watch(listener_->fd(), io::Interest::readable, [this](io::Readiness) { on_listener_ready(); });
      !watched) {
    context_->logger.log(LogLevel::error, watched.error().message() + ": the TCP port stays closed after the power cycle");
  }
}

}  // namespace ldoem::endpoints
