#include "ldoem/endpoints/memory_endpoint.hpp"

namespace ldoem::endpoints {

std::optional<OpenFailure> MemoryEndpoint::open(EndpointContext& context) {
  context_ = &context;
  context.out << "memory\n";
  return std::nullopt;
}

void MemoryEndpoint::send(ConnectionId to, protocol::ByteView payload) {
  if (closed_.contains(to.index)) return;  // as a socket: nobody is there any more
  sent_.push_back(Sent{context_->scheduler.now(), to.index, protocol::Bytes(payload.begin(), payload.end())});
}

void MemoryEndpoint::host_sends(std::uint32_t index, protocol::Bytes payload) {
  ++context_->activity;
  closed_.erase(index);  // a new connection under the same number
  context_->sink.on_telegram(ConnectionId{kind_, index}, std::move(payload));
}

void MemoryEndpoint::host_sends_bad_frame(std::uint32_t index, const protocol::FramingError& error) {
  ++context_->activity;
  context_->sink.on_framing_error(ConnectionId{kind_, index}, error);
}

void MemoryEndpoint::host_closes(std::uint32_t index) {
  ++context_->activity;
  closed_.insert(index);
  busy_.erase(index);
  context_->sink.on_connection_closed(ConnectionId{kind_, index});
}

void MemoryEndpoint::set_busy(std::uint32_t index, bool busy) {
  if (busy) {
    busy_.insert(index);
  } else {
    busy_.erase(index);
  }
}

std::vector<MemoryEndpoint::Sent> MemoryEndpoint::take_sent() {
  std::vector<Sent> taken(std::make_move_iterator(sent_.begin()), std::make_move_iterator(sent_.end()));
  sent_.clear();
  return taken;
}

}  // namespace ldoem::endpoints
