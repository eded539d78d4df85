// The LD's Ethernet port (spec 4.1): a TCP listener; every accepted session is its own
// connection (tcp#1, tcp#2, ...) with its deframer and a bounded output queue. A host that stops
// reading is dropped once its queue is full; a frame left half sent is dropped after the
// inter-byte timeout, and a connection that stays silent or idle too long is closed (HostLimits).
// Beyond HostLimits::max_tcp_clients connections at once, a new one is accepted and closed.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/endpoints/host_limits.hpp"
#include "ldoem/endpoints/output_queue.hpp"
#include "ldoem/base/warning_throttle.hpp"
#include "ldoem/io/tcp.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace ldoem::endpoints {

class TcpHostEndpoint final : public HostEndpoint {
 public:
  TcpHostEndpoint(std::string address, std::uint16_t port, HostLimits limits = {},
              ConnectionIndices indices = ConnectionIndices())
      : address_(std::move(address)), port_(port), limits_(limits), indices_(indices) {}

  std::string_view name() const override { return "tcp"; }
  std::optional<protocol::Transport> transport() const override { return protocol::Transport::tcp; }
  std::optional<OpenFailure> open(EndpointContext& context) override;
  bool busy(ConnectionId connection) const override;
  void send(ConnectionId to, protocol::ByteView payload) override;
  void close() override;
  void disconnect(ConnectionId connection) override;
  void set_power(DevicePower power) override;

  // The port actually listened on (the one asked for, or the kernel's pick for 0).
  std::optional<std::uint16_t> port() const;

 private:
  struct Client {
    io::TcpConnection connection;
    protocol::TcpDeframer deframer;
    OutputQueue output;
    // D11 tcp_stall and bandwidth (only with a fault hook): the deadline that resumes reading and
    // writing, or writes the next paced piece; whether the descriptor is unwatched (stalled).
    std::optional<Scheduler::Key> fault_resume;
    bool stalled = false;
    SimTime wire_free_at{};  // bandwidth: when the last paced piece was on the wire
    std::chrono::steady_clock::time_point last_received;
    bool spoke = false;  // a complete telegram arrived (silent_timeout no longer applies)
    std::optional<io::EventLoop::TimerId> inter_byte_timer;
    std::optional<io::EventLoop::TimerId> quiet_timer;  // silent_timeout, then idle_timeout
  };

  void on_listener_ready();
  void free_places_of_gone_hosts();
  void rest_listener(const std::string& why);
  void resume_listener();
  void on_client_ready(std::uint32_t index, io::Readiness readiness);
  void flush(std::uint32_t index);
  // Closes the connection (with a RST when `reset`) and tells the sink.
  void drop(std::uint32_t index, std::string_view why, bool reset = false);
  // D11 (tcp_endpoint_faults.cpp): true when the fault hook holds the connection's reading or
  // writing back; the deadline that lets it go on is then queued.
  bool stalled(std::uint32_t index, Client& client);
  bool paced(std::uint32_t index, Client& client);
  void resume_after_fault(std::uint32_t index);
  // D11 power_cycle (tcp_endpoint_faults.cpp): dark, connections from before reset, awake.
  void go_dark();
  void reset_dark_connections();
  void wake();
  void after_receive(std::uint32_t index);
  void on_inter_byte_timeout(std::uint32_t index);
  void arm_quiet_timer(std::uint32_t index, std::chrono::steady_clock::time_point at);
  void on_quiet_timer(std::uint32_t index);

  std::string address_;
  std::uint16_t port_;
  EndpointContext* context_ = nullptr;
  std::optional<io::TcpListener> listener_;
  HostLimits limits_;
  ConnectionIndices indices_;
  std::map<std::uint32_t, Client> clients_;

  static constexpr std::chrono::milliseconds kListenerRest{100};
  static constexpr std::chrono::seconds kWarnPeriod{10};
  static constexpr std::size_t kAcceptBudget = 16;  // connections accepted per loop round
  bool listener_resting_ = false;
  bool dark_ = false;  // D11 power_cycle: off or booting (set_power)
  io::EventLoop::TimerId resume_timer_ = 0;
  base::WarningThrottle rest_warning_{kWarnPeriod};     // out of descriptors
  base::WarningThrottle refused_warning_{kWarnPeriod};  // --max-clients reached

 public:
  std::uint64_t listener_rests() const { return listener_rests_; }  // accept() out of descriptors

 private:
  std::uint64_t listener_rests_ = 0;
};

}  // namespace ldoem::endpoints
