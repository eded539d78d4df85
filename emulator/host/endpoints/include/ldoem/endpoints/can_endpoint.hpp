// The LD's CAN port (D1): one raw CAN socket, one ISO-TP channel per host identifier pair
// (can#1, can#2, ...), and with the D9 effect bus_timing a pacer that lets our frames leave at
// the configured bit rate. Pair 1 follows the flash's CAN configuration (SET_CONFIG key 2)
// unless the pairs were given on the command line.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "ldoem/endpoints/can_bus_pacer.hpp"
#include "ldoem/endpoints/can_frame_backlog.hpp"
#include "ldoem/endpoints/can_id_pair.hpp"
#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/endpoints/isotp_channel.hpp"
#include "ldoem/io/can_socket.hpp"

namespace ldoem::endpoints {

struct CanEndpointSetup {
  std::string interface_name = "vcan0";
  std::vector<CanIdPair> pairs;  // empty: one pair, from `config` (D1 via flash)
  protocol::CanConfig config;    // the control unit's RAM CAN configuration at power-up
  bool bus_timing = false;       // D9: pace our frames at the bit rate
};

class CanHostEndpoint final : public HostEndpoint {
 public:
  explicit CanHostEndpoint(CanEndpointSetup setup) : setup_(std::move(setup)) {}

  std::string_view name() const override { return "can"; }
  std::optional<protocol::Transport> transport() const override { return protocol::Transport::can; }
  std::optional<OpenFailure> open(EndpointContext& context) override;
  bool busy(ConnectionId connection) const override;
  void send(ConnectionId to, protocol::ByteView payload) override;
  void close() override {}
  bool waiting_for_host() const override;
  void apply_can_config(const protocol::CanConfig& config) override;
  // D11 power_cycle: while off or booting, frames from hosts are read and lost (no flow control
  // either) and nothing is sent; at power-off every transfer under way is forgotten.
  void set_power(DevicePower power) override;
  void add_counters(Counters& counters) const override;

 private:
  void on_ready(io::Readiness readiness);
  // Frames out, the channel's deadline re-queued; telegrams from the host to the sink.
  void handle_input(std::size_t channel, IsoTpChannelOutput output);
  void transmit(std::size_t channel, const std::vector<protocol::CanFrame>& frames);
  void schedule_poll(std::size_t channel);
  void release_paced_frames(SimTime at);
  void flush_backlog();
  void note_dropped_frames(std::size_t count);
  void set_filters();
  // A fresh channel in place of `channel` (its transfers forgotten, its counts kept).
  void renew_channel(std::size_t channel, const IsoTpChannelConfig& config);
  // D11 (can_endpoint_faults.cpp): a host's first frame answered with FC overflow or held with
  // FC WAIT; false when the frame goes to the channel as usual.
  bool first_frame_faulted(std::size_t channel, const protocol::CanFrame& frame);
  void keep_host_waiting(std::size_t channel);
  void release_held_first_frame(std::size_t channel, bool deliver);
  protocol::CanFrame flow_control(std::size_t channel, protocol::IsoTpFlowStatus status) const;

  struct HeldFirstFrame {
    protocol::CanFrame frame;
    std::optional<Scheduler::Key> next_wait;  // the next FC WAIT
  };

  CanEndpointSetup setup_;
  EndpointContext* context_ = nullptr;
  std::optional<io::CanRawSocket> socket_;
  std::vector<IsoTpChannel> channels_;  // channel i is ConnectionId{can, i + 1}
  std::vector<std::optional<Scheduler::Key>> scheduled_polls_;  // the one queued poll per channel
  CanFrameBacklog backlog_;                 // frames the interface's queue refused, bounded
  std::optional<CanBusPacer> pacer_;        // D9 bus_timing only: frames leave at the bit rate
  std::optional<SimTime> pacer_scheduled_;  // the pacer's release deadline already queued
  IsoTpChannelCounters retired_;            // counts of channels replaced by a new CAN configuration
  std::vector<std::optional<HeldFirstFrame>> held_;  // D11 isotp_fc_wait, per channel (fault hook only)
  bool dark_ = false;  // D11 power_cycle: off or booting
};

}  // namespace ldoem::endpoints
