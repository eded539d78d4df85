// One host on the CAN bus (D1): an identifier pair with its ISO-TP receiver and sender, and the
// telegrams waiting to be sent. Pure glue over protocol/isotp.hpp: frames and time in, frames
// and telegrams out; the CAN endpoint owns the socket.
//
// D10: each telegram is one ISO-TP message; the sender carries one at a time, the rest wait in
// a bounded queue (a host that never sends flow control times out after N_Bs = 1 s per message,
// so the queue drains). busy() is D10's "still sending the previous profile".
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "ldoem/endpoints/can_id_pair.hpp"
#include "ldoem/endpoints/wire_fault_hook.hpp"
#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/can_frame.hpp"
#include "ldoem/protocol/isotp.hpp"

namespace ldoem::endpoints {

using base::SimTime;

inline constexpr std::size_t kIsoTpMaxQueuedTelegrams = 16;

struct IsoTpChannelConfig {
  CanIdPair ids;
  std::uint8_t block_size = 0;       // our flow control's BS (D1: 0 unless configured)
  SimTime st_min = SimTime::zero();  // our flow control's STmin (D1: 0 unless configured)
  bool pad_frames = false;           // D1: unpadded unless configured
  std::size_t max_queued_telegrams = kIsoTpMaxQueuedTelegrams;
  std::uint32_t max_wait_frames = protocol::kIsoTpDefaultMaxWaitFrames;  // N_WFTmax for our sender
};

struct IsoTpChannelOutput {
  std::vector<protocol::Bytes> telegrams;  // complete telegrams from the host
  std::vector<protocol::CanFrame> frames;  // put these on the bus now, in order
};

struct IsoTpChannelCounters {
  std::uint64_t receive_errors = 0;    // D1: partial telegrams dropped, stray or malformed frames
  std::uint64_t send_failures = 0;     // messages abandoned (N_Bs timeout, host FC overflow)
  std::uint64_t queue_overflows = 0;   // telegrams refused because the queue was full
  std::uint64_t telegrams_received = 0;
  std::uint64_t telegrams_sent = 0;
};

// D11 garbage on CAN: `bytes` as frames of up to 8 data bytes on `id`, each one's first byte with
// the high nibble 2 (a consecutive-frame PCI: a receiver with no reception running ignores it,
// ISO 15765-2), so stray bytes never start or end a message.
std::vector<protocol::CanFrame> garbage_frames(std::uint32_t id, protocol::ByteView bytes);

class IsoTpChannel {
 public:
  explicit IsoTpChannel(IsoTpChannelConfig config);

  // Frames on the host's request identifier belong to this channel (data and the host's flow
  // control for our sender).
  bool accepts(const protocol::CanFrame& frame) const { return frame.id == config_.ids.request_id; }

  IsoTpChannelOutput on_frame(SimTime now, const protocol::CanFrame& frame);
  // Queues one telegram (service WORD first) as one ISO-TP message; starts it when idle.
  IsoTpChannelOutput send(SimTime now, protocol::ByteView telegram);
  // The same with D11 wire faults: `faults.garbage_before` goes out as stray frames right before
  // the message (garbage_frames), and its first consecutive frame is dropped, sent twice or sent
  // with the next sequence number.
  IsoTpChannelOutput send(SimTime now, protocol::ByteView telegram, TelegramFaults faults);
  // Call at or after deadline(): N_Cr/N_Bs timeouts and frames held back by STmin.
  IsoTpChannelOutput poll(SimTime now);
  std::optional<SimTime> deadline() const;

  // A message in flight or waiting (D10 busy).
  bool busy() const { return sender_.busy() || !queue_.empty(); }
  // The next deadline is a timeout on the host (N_Bs for its flow control, N_Cr for its next
  // frame), not our own pacing: a virtual clock must not jump over it while the host is alive.
  bool waiting_for_host() const {
    return sender_.state() == protocol::IsoTpSender::State::waiting_for_flow_control ||
           receiver_.state() == protocol::IsoTpReceiver::State::receiving;
  }
  const IsoTpChannelConfig& config() const { return config_; }
  const IsoTpChannelCounters& counters() const { return counters_; }

 private:
  struct Queued {
    protocol::Bytes telegram;
    std::vector<protocol::CanFrame> prelude;  // D11 garbage: stray frames before the message
    ConsecutiveFrameFault first_consecutive_frame = ConsecutiveFrameFault::none;
  };
  void pump(SimTime now, IsoTpChannelOutput& out);
  void put_out(const std::vector<protocol::CanFrame>& frames, IsoTpChannelOutput& out);
  void note_receive(protocol::IsoTpReceiveResult result, IsoTpChannelOutput& out);

  IsoTpChannelConfig config_;
  protocol::IsoTpReceiver receiver_;
  protocol::IsoTpSender sender_;
  std::deque<Queued> queue_;
  ConsecutiveFrameFault pending_frame_fault_ = ConsecutiveFrameFault::none;  // for the running message
  bool sender_counted_ = true;  // the sender's last message is already counted
  IsoTpChannelCounters counters_;
};

}  // namespace ldoem::endpoints
