// D11 tcp_stall and bandwidth inside the TCP endpoint (wire_fault_hook.hpp). Only reached when
// the daemon set a fault hook; otherwise tcp_endpoint.cpp never calls these.
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
bool TcpEndpoint::stalled(std::uint32_t index, Client& client) {
  if (client.stalled) return true;
  const SimTime now = context_->scheduler.now();
  const auto until = fault_hook_->stalled_until(ConnectionId{TransportKind::tcp, index}, now);
  if (!until || *until <= now) return false;
  if (client.fault_resume) context_->scheduler.cancel(*client.fault_resume);  // a paced piece waits with the rest
  client.stalled = true;
  context_->loop.unwatch(client.connection.fd());
  client.fault_resume = context_->scheduler.add(*until, [this, index](SimTime) { resume_after_fault(index); });
  return true;
}

// bandwidth: one piece at a time, from a deadline; the socket is not watched for writing meanwhile.
bool TcpEndpoint::paced(std::uint32_t index, Client& client) {
  if (client.fault_resume) return true;  // the next piece is already due at its time
  if (client.output.empty()) return false;
  const SimTime now = context_->scheduler.now();
  const auto rate = fault_hook_->bytes_per_second(ConnectionId{TransportKind::tcp, index}, now);
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

void TcpEndpoint::resume_after_fault(std::uint32_t index) {
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

}  // namespace ldoem::endpoints
