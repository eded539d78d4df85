#include "ldoem/capture/capture_conversation.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <utility>
#include <type_traits>

namespace ldoem::capture {

// One direction of one TCP connection: where the next byte belongs and the frames so far.
struct ConversationExtractor::TcpDirection {
  protocol::TcpDeframer deframer;
  std::optional<std::uint32_t> next_sequence;
};

namespace {

protocol::IsoTpReceiverConfig receiver_config(std::uint32_t flow_control_id, const ConversationConfig& conversation) {
  protocol::IsoTpReceiverConfig config;
  config.flow_control_id = flow_control_id;
  config.max_message_bytes = conversation.max_telegram_bytes;
  config.n_cr_timeout = conversation.isotp_gap_limit;
  return config;
}

}  // namespace

ConversationExtractor::ConversationExtractor(ConversationConfig config)
    : config_(config),
      can_requests_(receiver_config(config.response_can_id, config)),
      can_replies_(receiver_config(config.request_can_id, config)) {
  config_.tcp_port = config_.tcp_port.value_or(base::kHostTcpPort);
}

ConversationExtractor::~ConversationExtractor() = default;

void ConversationExtractor::add(base::SimTime time, const LinkPayload& payload) {
  ++counters_.packets;
  std::visit(
      [&](const auto& value) {
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, TcpSegment>) {
          add_tcp(time, value);
        } else if constexpr (std::is_same_v<T, protocol::CanFrame>) {
          add_can(time, value);
        } else if constexpr (std::is_same_v<T, SerialChunk>) {
          add_serial(time, value);
        } else if constexpr (std::is_same_v<T, LptWrites>) {
          counters_.lpt_writes += value.values.size();
          ++counters_.ignored_packets;
        } else {
          ++counters_.ignored_packets;
        }
      },
      payload);
}

std::vector<CapturedTelegram> ConversationExtractor::take() {
  std::vector<CapturedTelegram> out;
  out.swap(telegrams_);
  return out;
}

void ConversationExtractor::add_tcp(base::SimTime time, const TcpSegment& segment) {
  protocol::WireDirection direction;
  if (segment.destination_port == *config_.tcp_port) {
    direction = protocol::WireDirection::host_to_device;
  } else if (segment.source_port == *config_.tcp_port) {
    direction = protocol::WireDirection::device_to_host;
  } else {
    ++counters_.ignored_packets;
    return;
  }
  const bool to_device = direction == protocol::WireDirection::host_to_device;
  const auto connection_key = to_device
      ? std::tuple{segment.destination_ip, segment.destination_port, segment.source_ip, segment.source_port}
      : std::tuple{segment.source_ip, segment.source_port, segment.destination_ip, segment.destination_port};
  const FlowKey flow_key{segment.source_ip, segment.source_port, segment.destination_ip, segment.destination_port};
  const bool opening = (segment.flags & kTcpSyn) != 0;
  auto connection = connections_.find(connection_key);
  if (connection == connections_.end()) {
    connection = connections_.emplace(connection_key, next_connection_++).first;
  } else if (opening && to_device) {
    connection->second = next_connection_++;  // a new connection on a reused port pair
  }
  auto& flow = tcp_flows_[flow_key];
  if (!flow || opening) flow = std::make_unique<TcpDirection>();
  if (opening) {
    flow->next_sequence = segment.sequence + 1;
    return;
  }
  if ((segment.flags & kTcpRst) != 0) {
    flow = std::make_unique<TcpDirection>();
    return;
  }
  protocol::ByteView data(segment.payload);
  if (!data.empty()) {
    if (!flow->next_sequence) flow->next_sequence = segment.sequence;
    const auto ahead = static_cast<std::int32_t>(segment.sequence - *flow->next_sequence);
    if (ahead > 0) {
      // Bytes never captured: the frame in progress is lost, resynchronise on the next header.
      ++counters_.tcp_gaps;
      flow->deframer.reset();
      flow->next_sequence = segment.sequence;
    } else if (ahead < 0) {
      const auto repeated = static_cast<std::size_t>(-static_cast<std::int64_t>(ahead));
      data = repeated >= data.size() ? protocol::ByteView{} : data.subspan(repeated);
    }
    *flow->next_sequence += static_cast<std::uint32_t>(data.size());
    deliver(time, protocol::Transport::tcp, direction, connection->second, flow->deframer.feed(data));
  }
  if ((segment.flags & kTcpFin) != 0 && flow->next_sequence) *flow->next_sequence += 1;
}

void ConversationExtractor::add_can(base::SimTime time, const protocol::CanFrame& frame) {
  protocol::IsoTpReceiver* receiver = nullptr;
  protocol::WireDirection direction = protocol::WireDirection::host_to_device;
  if (frame.id == config_.request_can_id) {
    receiver = &can_requests_;
  } else if (frame.id == config_.response_can_id) {
    receiver = &can_replies_;
    direction = protocol::WireDirection::device_to_host;
  } else {
    ++counters_.ignored_packets;
    return;
  }
  const protocol::IsoTpReceiveResult result = receiver->on_frame(time, frame);
  if (result.error) ++counters_.framing_errors;
  if (result.message) {
    telegrams_.push_back(CapturedTelegram{time, protocol::Transport::can, direction, 0, *result.message});
  }
}

void ConversationExtractor::add_serial(base::SimTime time, const SerialChunk& chunk) {
  if (chunk.direction == protocol::WireDirection::host_to_device) {
    deliver(time, protocol::Transport::serial, chunk.direction, 0, serial_requests_.feed(chunk.bytes));
  } else {
    deliver(time, protocol::Transport::serial, chunk.direction, 0, serial_replies_.feed(chunk.bytes));
  }
}

void ConversationExtractor::deliver(base::SimTime time, protocol::Transport transport, protocol::WireDirection direction,
                                    std::uint32_t stream, std::vector<protocol::DeframerEvent> events) {
  for (auto& event : events) {
    if (auto* telegram = std::get_if<protocol::Telegram>(&event)) {
      telegrams_.push_back(CapturedTelegram{time, transport, direction, stream, std::move(telegram->payload)});
    } else {
      ++counters_.framing_errors;
    }
  }
}

std::optional<std::uint16_t> detect_device_tcp_port(const std::vector<DecodedPacket>& packets) {
  struct Candidate {
    std::set<std::pair<std::uint32_t, std::uint16_t>> peers;  // the other ends it exchanged frames with
    bool first_receiver = false;
  };
  std::map<std::uint16_t, Candidate> candidates;
  std::set<std::uint16_t> syn_targets;
  bool first = true;
  for (const auto& packet : packets) {
    const auto* segment = std::get_if<TcpSegment>(&packet.payload);
    if (segment == nullptr) continue;
    if ((segment->flags & (kTcpSyn | kTcpAck)) == kTcpSyn) syn_targets.insert(segment->destination_port);
    const protocol::ByteView data(segment->payload);
    if (data.size() < protocol::kTcpMagic.size() || !std::equal(protocol::kTcpMagic.begin(), protocol::kTcpMagic.end(), data.begin())) {
      continue;
    }
    candidates[segment->destination_port].peers.emplace(segment->source_ip, segment->source_port);
    candidates[segment->source_port].peers.emplace(segment->destination_ip, segment->destination_port);
    if (first) candidates[segment->destination_port].first_receiver = true;
    first = false;
  }
  std::optional<std::uint16_t> best;
  auto rank = [&](std::uint16_t port) {
    const Candidate& candidate = candidates.at(port);
    return std::tuple{candidate.peers.size(), syn_targets.count(port) > 0, candidate.first_receiver};
  };
  for (const auto& [port, candidate] : candidates) {
    if (!best || rank(port) > rank(*best)) best = port;
  }
  return best;
}

Conversation extract_conversation(const std::vector<DecodedPacket>& packets, ConversationConfig config) {
  Conversation conversation;
  if (!config.tcp_port) {
    const auto detected = detect_device_tcp_port(packets);
    conversation.tcp_port_detected = detected.has_value();
    config.tcp_port = detected.value_or(base::kHostTcpPort);
  }
  conversation.tcp_port = *config.tcp_port;
  ConversationExtractor extractor(config);
  for (const auto& packet : packets) {
    extractor.add(packet.time, packet.payload);
    for (auto& telegram : extractor.take()) conversation.telegrams.push_back(std::move(telegram));
  }
  conversation.counters = extractor.counters();
  return conversation;
}

std::vector<Exchange> exchanges_of(const std::vector<CapturedTelegram>& telegrams, protocol::Transport transport) {
  std::vector<Exchange> exchanges;
  base::SimTime request_time{};
  for (const auto& telegram : telegrams) {
    if (telegram.transport != transport) continue;
    if (telegram.direction == protocol::WireDirection::host_to_device) {
      exchanges.push_back(Exchange{telegram.payload, {}});
      request_time = telegram.time;
    } else if (!exchanges.empty()) {
      const base::SimTime delay = std::max(base::SimTime::zero(), telegram.time - request_time);
      exchanges.back().answers.push_back(RecordedAnswer{delay, telegram.payload});
    }
  }
  return exchanges;
}

std::optional<protocol::Transport> busiest_transport(const std::vector<CapturedTelegram>& telegrams) {
  std::map<protocol::Transport, std::size_t> counts;
  for (const auto& telegram : telegrams) ++counts[telegram.transport];
  std::optional<protocol::Transport> best;
  std::size_t most = 0;
  for (const auto& [transport, count] : counts) {
    if (count > most) {
      most = count;
      best = transport;
    }
  }
  return best;
}

}  // namespace ldoem::capture
