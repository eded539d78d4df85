// A host link without a socket: the test is the host. It hands telegram payloads in
// (host_sends), reads what the device sent (take_sent), makes a connection busy (D10) or closes
// it. Most daemon tests run on it: no port, no pty, no timing of the kernel in the way.
//
// Use: create it, hand it to the daemon (Daemon::create's extra endpoints) and keep a pointer;
// every call happens on the test's thread between the daemon's loop rounds.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <set>
#include <vector>

#include "ldoem/endpoints/host_endpoint.hpp"

namespace ldoem::endpoints {

class MemoryEndpoint final : public HostEndpoint {
 public:
  struct Sent {
    SimTime at{};
    std::uint32_t index = 0;
    protocol::Bytes payload;
  };

  explicit MemoryEndpoint(protocol::Transport kind = protocol::Transport::tcp) : kind_(kind) {}

  std::string_view name() const override { return "memory"; }
  std::optional<protocol::Transport> transport() const override { return kind_; }
  std::optional<OpenFailure> open(EndpointContext& context) override;
  bool busy(ConnectionId connection) const override { return busy_.contains(connection.index); }
  void send(ConnectionId to, protocol::ByteView payload) override;
  void close() override {}
  void disconnect(ConnectionId connection) override { host_closes(connection.index); }
  void apply_can_config(const protocol::CanConfig& config) override { can_configs_.push_back(config); }

  // --- the host's side ---
  // A telegram from connection `index` (payload: service WORD first, no framing).
  void host_sends(std::uint32_t index, protocol::Bytes payload);
  // A frame of `index` its deframer dropped (D2).
  void host_sends_bad_frame(std::uint32_t index, const protocol::FramingError& error);
  void host_closes(std::uint32_t index);
  // D10: while busy, profiles due for `index` are skipped.
  void set_busy(std::uint32_t index, bool busy);
  // Everything the device sent since the last call, in order, all connections.
  std::vector<Sent> take_sent();
  std::size_t sent_count() const { return sent_.size(); }
  // Every CAN configuration the device passed on (D1), in order.
  const std::vector<protocol::CanConfig>& can_configs() const { return can_configs_; }

 private:
  protocol::Transport kind_;
  EndpointContext* context_ = nullptr;
  std::set<std::uint32_t> busy_;
  std::set<std::uint32_t> closed_;
  std::deque<Sent> sent_;
  std::vector<protocol::CanConfig> can_configs_;
};

}  // namespace ldoem::endpoints
