// The tilt stepper's parallel port as a pseudo-terminal (D8): every byte a host writes is the
// new value of the data register, stamped with its arrival time. It carries no telegrams.
//
// D8: a host pulses the stepper, then asks for the next profile; the bytes, written first, must
// count first. They are watched first in each loop round, and since the kernel hands pty bytes
// on through a work queue (a register byte written just before a TCP request can become
// readable just after it), the device also asks for them before serving each telegram
// (take_pending_input).
#pragma once

#include <filesystem>
#include <optional>

#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/io/pseudo_terminal.hpp"

namespace ldoem::endpoints {

class LptPtyEndpoint final : public HostEndpoint {
 public:
  explicit LptPtyEndpoint(std::filesystem::path link_path) : link_path_(std::move(link_path)) {}

  std::string_view name() const override { return "lpt"; }
  std::optional<protocol::Transport> transport() const override { return std::nullopt; }
  std::optional<OpenFailure> open(EndpointContext& context) override;
  bool busy(ConnectionId) const override { return false; }
  void send(ConnectionId, protocol::ByteView) override {}
  void close() override {}
  void take_pending_input() override;

 private:
  void on_ready();
  std::uint8_t as_the_plate_sees(SimTime at, std::uint8_t value);

  std::filesystem::path link_path_;
  EndpointContext* context_ = nullptr;
  std::optional<io::PseudoTerminal> pty_;
  std::uint8_t seen_by_plate_ = 0;  // D11 (fault hook only): the last register value passed on
};

}  // namespace ldoem::endpoints
