// From captured packets to the telegrams they carried: TCP segments reassembled per connection
// and direction and deframed (spec 4.1), serial bytes deframed (spec 4.2), CAN frames on the D1
// identifiers reassembled by ISO-TP. Pure: packets and their times go in, telegrams come out.
// The replay tool and `ldoem-conformance --against` are built on it (docs/capture.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <vector>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/protocol/bytes.hpp"
#include "ldoem/capture/capture_packets.hpp"
#include "ldoem/protocol/isotp.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/base/sim_time.hpp"
#include "ldoem/protocol/tcp_framing.hpp"
#include "ldoem/protocol/transport.hpp"

namespace ldoem::capture {

struct CapturedTelegram {
  base::SimTime time{};  // when its last byte or frame was captured
  protocol::Transport transport = protocol::Transport::tcp;
  protocol::WireDirection direction = protocol::WireDirection::host_to_device;
  std::uint32_t stream = 0;  // TCP: connection index in order of appearance; serial, CAN: 0
  protocol::Bytes payload;             // service WORD then parameters
  bool operator==(const CapturedTelegram&) const = default;
};

struct ConversationConfig {
  // The device's TCP port. Unset: extract_conversation detects it (detect_device_tcp_port), a
  // ConversationExtractor on its own takes 49152 (spec 4.1).
  std::optional<std::uint16_t> tcp_port;
  std::uint32_t request_can_id = protocol::kIsoTpHostToDeviceId;   // D1
  std::uint32_t response_can_id = protocol::kIsoTpDeviceToHostId;  // D1
  // ISO-TP reassembly bound. Profiles over CAN may exceed D3's 5816 bytes (D1 has no limit).
  std::size_t max_telegram_bytes = protocol::kIsoTpDefaultMaxMessageBytes;
  // How long a recorded ISO-TP message may pause between frames. Not D1's N_Cr: a capture is
  // read after the fact, and a recording host that was briefly descheduled (a loaded CI
  // machine, UML) stamps late frames that the live receiver still took in time.
  base::SimTime isotp_gap_limit = std::chrono::seconds(30);
};

// What could not be turned into telegrams, so a user sees a capture's gaps instead of guessing.
struct ConversationCounters {
  std::uint64_t packets = 0;
  std::uint64_t ignored_packets = 0;  // other protocols, ports, identifiers, LPT writes
  std::uint64_t framing_errors = 0;   // bad checksums, CRCs, hex, broken ISO-TP sequences
  std::uint64_t tcp_gaps = 0;         // bytes missing in a TCP stream (capture lost packets)
  std::uint64_t lpt_writes = 0;
};

class ConversationExtractor {
 public:
  explicit ConversationExtractor(ConversationConfig config = {});
  ~ConversationExtractor();
  ConversationExtractor(const ConversationExtractor&) = delete;
  ConversationExtractor& operator=(const ConversationExtractor&) = delete;

  void add(base::SimTime time, const LinkPayload& payload);
  // Telegrams completed so far, in capture order; the internal list is emptied.
  std::vector<CapturedTelegram> take();
  const ConversationCounters& counters() const { return counters_; }

 private:
  struct TcpDirection;
  using FlowKey = std::tuple<std::uint32_t, std::uint16_t, std::uint32_t, std::uint16_t>;
  void add_tcp(base::SimTime time, const TcpSegment& segment);
  void add_can(base::SimTime time, const protocol::CanFrame& frame);
  void add_serial(base::SimTime time, const SerialChunk& chunk);
  void deliver(base::SimTime time, protocol::Transport transport, protocol::WireDirection direction, std::uint32_t stream,
               std::vector<protocol::DeframerEvent> events);

  ConversationConfig config_;
  ConversationCounters counters_;
  std::map<FlowKey, std::unique_ptr<TcpDirection>> tcp_flows_;  // key: source then destination
  std::map<FlowKey, std::uint32_t> connections_;  // key: device then host
  std::uint32_t next_connection_ = 0;
  protocol::IsoTpReceiver can_requests_;
  protocol::IsoTpReceiver can_replies_;
  protocol::SerialDeframer serial_requests_;
  protocol::SerialReplyReassembler serial_replies_;
  std::vector<CapturedTelegram> telegrams_;
};

// All telegrams of a list of (time, payload) packets in one go.
struct DecodedPacket {
  base::SimTime time{};
  LinkPayload payload;
};
struct Conversation {
  std::vector<CapturedTelegram> telegrams;
  ConversationCounters counters;
  std::uint16_t tcp_port = base::kHostTcpPort;  // the device port its TCP telegrams were taken from
  bool tcp_port_detected = false;               // found by detect_device_tcp_port, not given
};
Conversation extract_conversation(const std::vector<DecodedPacket>& packets, ConversationConfig config = {});

// The LD-OEM's TCP port in a capture of any port: the port of the TCP segments that begin with
// the frame header STX "USP" (spec 4.1). Of two candidates (one connection: both its ports carry
// frames), the one more connections reach, then the one a SYN was sent to, then the receiver of
// the first frame (the host speaks first). Nothing when no segment begins with the header.
std::optional<std::uint16_t> detect_device_tcp_port(const std::vector<DecodedPacket>& packets);

// A conversation cut into exchanges: one request from the host and every telegram the device
// sent after it until the next request (its reply, and the profiles a GET_PROFILE streamed),
// each with its delay after the request. Used by ldoem-emud --replay and ldoem-conformance --against.
struct RecordedAnswer {
  base::SimTime delay{};
  protocol::Bytes payload;
  bool operator==(const RecordedAnswer&) const = default;
};
struct Exchange {
  protocol::Bytes request;
  std::vector<RecordedAnswer> answers;
  bool operator==(const Exchange&) const = default;
};

// The exchanges of one transport (all its streams, in capture order). What the device sent
// before the first request is dropped.
std::vector<Exchange> exchanges_of(const std::vector<CapturedTelegram>& telegrams, protocol::Transport transport);

// The transport with the most telegrams, or nothing for an empty conversation.
std::optional<protocol::Transport> busiest_transport(const std::vector<CapturedTelegram>& telegrams);

}  // namespace ldoem::capture
