// The tilt stepper's parallel port as three gpio lines DIR, CLK, MODE = DATA0..2 (D8, the
// gpio back end): the levels before any edge, then each edge at its kernel timestamp. It
// carries no telegrams.
#pragma once

#include <optional>
#include <string>

#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/io/gpio_lines.hpp"

namespace ldoem::endpoints {

class LptGpioEndpoint final : public HostEndpoint {
 public:
  explicit LptGpioEndpoint(std::string chip) : chip_(std::move(chip)) {}

  std::string_view name() const override { return "lpt-gpio"; }
  std::optional<protocol::Transport> transport() const override { return std::nullopt; }
  std::optional<OpenFailure> open(EndpointContext& context) override;
  bool busy(ConnectionId) const override { return false; }
  void send(ConnectionId, protocol::ByteView) override {}
  void close() override {}

 private:
  void on_ready();
  bool step_lost(SimTime at, bool level);

  std::string chip_;  // chip path, name or label
  EndpointContext* context_ = nullptr;
  std::optional<io::GpioLineReader> reader_;
  bool clock_edge_lost_ = false;  // D11 (fault hook only): the plate missed the last rising edge
};

}  // namespace ldoem::endpoints
