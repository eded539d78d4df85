// The LD's RS-232/RS-422 port (spec 4.2) as a pseudo-terminal: one connection, serial#1. Bytes
// nobody reads are lost, as on a real line; a package left incomplete for the inter-byte timeout
// is dropped (spec 6), so its start is never joined to the next one.
#pragma once

#include <filesystem>
#include <optional>

#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/endpoints/host_limits.hpp"
#include "ldoem/endpoints/output_queue.hpp"
#include "ldoem/io/pseudo_terminal.hpp"
#include "ldoem/protocol/serial_framing.hpp"

namespace ldoem::endpoints {

class SerialHostEndpoint final : public HostEndpoint {
 public:
  explicit SerialHostEndpoint(std::filesystem::path link_path,
                          std::chrono::milliseconds inter_byte_timeout = kDefaultInterByteTimeout)
      : link_path_(std::move(link_path)), inter_byte_timeout_(inter_byte_timeout) {}

  std::string_view name() const override { return "serial"; }
  std::optional<protocol::Transport> transport() const override { return protocol::Transport::serial; }
  std::optional<OpenFailure> open(EndpointContext& context) override;
  bool busy(ConnectionId) const override { return !output_.empty(); }
  void send(ConnectionId to, protocol::ByteView payload) override;
  void close() override { flush(); }
  // D11 power_cycle: while off or booting, what arrives is read and lost (a switched-off UART
  // hears nothing) and nothing is written; at power-off what was queued is gone.
  void set_power(DevicePower power) override;

 private:
  void on_ready(io::Readiness readiness);
  void flush();
  protocol::Bytes faulty_reply(ConnectionId to, protocol::ByteView payload);
  void note_echo_resets();
  void on_inter_byte_timeout();

  std::filesystem::path link_path_;
  std::chrono::milliseconds inter_byte_timeout_;  // 0: never
  std::optional<io::EventLoop::TimerId> inter_byte_timer_;
  EndpointContext* context_ = nullptr;
  std::optional<io::PseudoTerminal> pty_;
  protocol::SerialDeframer deframer_;
  OutputQueue output_;
  std::uint64_t echo_resets_logged_ = 0;
  std::uint64_t next_echo_report_ = 1;
  bool dark_ = false;  // D11 power_cycle: off or booting
};

}  // namespace ldoem::endpoints
