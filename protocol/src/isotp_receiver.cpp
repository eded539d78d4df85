// ISO-TP receiver: SF, FF (12-bit and 32-bit length), CF with sequence check, our flow control,
// N_Cr timeout (D1). Errors drop the partial telegram and are counted; nothing is sent for them.
#include <algorithm>
#include <cassert>

#include "ldoem/protocol/isotp.hpp"
#include "isotp_pci.hpp"

namespace ldoem::protocol {

namespace {

constexpr std::size_t kShortFirstFrameHeaderBytes = 2;    // 1H LL
constexpr std::size_t kEscapedFirstFrameHeaderBytes = 6;  // 10 00 LL LL LL LL
// A message of 7 bytes or fewer fits a single frame; a first frame announcing one is invalid.
constexpr std::size_t kMinFirstFrameLength = kIsoTpMaxSingleFrameBytes + 1;

struct FirstFrameHeader {
  std::uint64_t message_length;
  std::size_t header_bytes;
};

// Nothing when the frame is not a valid first frame on classic CAN.
std::optional<FirstFrameHeader> parse_first_frame(const CanFrame& frame) {
  // A first frame always fills the frame: it is never the last frame of a message.
  if (frame.length != kCanMaxDataBytes) {
    return std::nullopt;
  }
  const std::uint32_t short_length =
      (static_cast<std::uint32_t>(frame.data[0] & detail::kPciLowNibble) << 8) | frame.data[1];
  if (short_length != 0) {
    if (short_length < kMinFirstFrameLength) {
      return std::nullopt;
    }
    return FirstFrameHeader{short_length, kShortFirstFrameHeaderBytes};
  }
  const std::uint32_t escaped_length = read_u32_be(frame.payload(), 2);
  // The escape is only for lengths the 12-bit field cannot hold.
  if (escaped_length <= kIsoTpMaxShortFirstFrameLength) {
    return std::nullopt;
  }
  return FirstFrameHeader{escaped_length, kEscapedFirstFrameHeaderBytes};
}

// The counter an error adds to.
std::uint64_t& counter_of(IsoTpReceiverCounters& counters, IsoTpReceiveError error) {
  switch (error) {
    case IsoTpReceiveError::bad_sequence: return counters.bad_sequence;
    case IsoTpReceiveError::unexpected_frame: return counters.unexpected_frame;
    case IsoTpReceiveError::too_large: return counters.too_large;
    case IsoTpReceiveError::timeout: return counters.timeout;
    case IsoTpReceiveError::malformed: return counters.malformed;
  }
  return counters.malformed;  // not reached: the switch names every error
}

}  // namespace

IsoTpReceiver::IsoTpReceiver(IsoTpReceiverConfig config)
    : config_(config), st_min_byte_(encode_st_min(config.st_min)) {}

IsoTpReceiveResult IsoTpReceiver::on_frame(base::SimTime now, const CanFrame& frame) {
  IsoTpReceiveResult result;
  const bool timed_out = state_ == State::receiving && now >= consecutive_frame_deadline_;
  if (timed_out) {
    drop(IsoTpReceiveError::timeout, result);
  }
  const std::optional<IsoTpFrameType> type = isotp_frame_type(frame);
  if (frame.length > kCanMaxDataBytes || !type) {
    count(IsoTpReceiveError::malformed, result);  // ignored; a running reception goes on
    return result;
  }
  if (timed_out && *type == IsoTpFrameType::consecutive_frame) {
    return result;  // the late remainder of the telegram just dropped
  }
  switch (state_) {
    case State::idle:
      on_frame_idle(now, *type, frame, result);
      return result;
    case State::receiving:
      on_frame_receiving(now, *type, frame, result);
      return result;
  }
  assert(false && "unreachable receiver state");
  return result;
}

void IsoTpReceiver::on_frame_idle(base::SimTime now, IsoTpFrameType type, const CanFrame& frame,
                                  IsoTpReceiveResult& result) {
  switch (type) {
    case IsoTpFrameType::single_frame:
      accept_single_frame(frame, result);
      return;
    case IsoTpFrameType::first_frame:
      accept_first_frame(now, frame, result);
      return;
    case IsoTpFrameType::consecutive_frame:
      count(IsoTpReceiveError::unexpected_frame, result);  // no FF before it
      return;
    case IsoTpFrameType::flow_control:
      return;  // belongs to the sender of this identifier pair
  }
}

void IsoTpReceiver::on_frame_receiving(base::SimTime now, IsoTpFrameType type,
                                       const CanFrame& frame, IsoTpReceiveResult& result) {
  switch (type) {
    // ISO 15765-2: a new SF or FF ends the running reception (unexpected_frame) and starts a
    // new one. Only a valid one does: a malformed frame is ignored and the reception goes on.
    case IsoTpFrameType::single_frame:
      accept_single_frame(frame, result);
      return;
    case IsoTpFrameType::first_frame:
      accept_first_frame(now, frame, result);
      return;
    case IsoTpFrameType::consecutive_frame:
      accept_consecutive_frame(now, frame, result);
      return;
    case IsoTpFrameType::flow_control:
      return;
  }
}

void IsoTpReceiver::accept_single_frame(const CanFrame& frame, IsoTpReceiveResult& result) {
  const std::size_t message_length = frame.data[0] & detail::kPciLowNibble;
  // SF_DL 0 is the CAN FD escape and 8..15 cannot fit a classic frame; the DLC must cover it.
  if (message_length == 0 || message_length > kIsoTpMaxSingleFrameBytes ||
      message_length + 1 > frame.length) {
    count(IsoTpReceiveError::malformed, result);
    return;
  }
  if (state_ == State::receiving) {
    drop(IsoTpReceiveError::unexpected_frame, result);
  }
  if (message_length > config_.max_message_bytes) {
    count(IsoTpReceiveError::too_large, result);
    return;
  }
  const ByteView bytes = frame.payload().subspan(1, message_length);
  result.message = Bytes(bytes.begin(), bytes.end());
  ++counters_.messages;
}

void IsoTpReceiver::accept_first_frame(base::SimTime now, const CanFrame& frame,
                                       IsoTpReceiveResult& result) {
  const std::optional<FirstFrameHeader> header = parse_first_frame(frame);
  if (!header) {
    count(IsoTpReceiveError::malformed, result);
    return;
  }
  if (state_ == State::receiving) {
    drop(IsoTpReceiveError::unexpected_frame, result);
  }
  if (header->message_length > config_.max_message_bytes) {
    count(IsoTpReceiveError::too_large, result);
    result.flow_control = flow_control(IsoTpFlowStatus::overflow);
    return;
  }
  expected_length_ = static_cast<std::size_t>(header->message_length);
  buffer_.clear();
  buffer_.reserve(expected_length_);  // bounded by max_message_bytes just above
  const ByteView first_bytes = frame.payload().subspan(header->header_bytes);
  buffer_.insert(buffer_.end(), first_bytes.begin(), first_bytes.end());
  next_sequence_ = 1;
  frames_left_in_block_ = config_.block_size;
  consecutive_frame_deadline_ = now + config_.n_cr_timeout;
  state_ = State::receiving;
  result.flow_control = flow_control(IsoTpFlowStatus::continue_to_send);
}

void IsoTpReceiver::accept_consecutive_frame(base::SimTime now, const CanFrame& frame,
                                             IsoTpReceiveResult& result) {
  const std::uint8_t sequence = frame.data[0] & detail::kPciLowNibble;
  if (sequence != next_sequence_) {
    drop(IsoTpReceiveError::bad_sequence, result);
    return;
  }
  const std::size_t wanted =
      std::min(expected_length_ - buffer_.size(), kIsoTpConsecutiveFrameBytes);
  if (frame.length < wanted + 1) {
    drop(IsoTpReceiveError::malformed, result);  // the bytes cannot come any more
    return;
  }
  const ByteView bytes = frame.payload().subspan(1, wanted);
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  next_sequence_ = static_cast<std::uint8_t>((next_sequence_ + 1) & detail::kPciLowNibble);  // 15 -> 0
  if (buffer_.size() == expected_length_) {
    result.message = std::move(buffer_);
    buffer_ = Bytes();
    state_ = State::idle;
    ++counters_.messages;
    return;
  }
  consecutive_frame_deadline_ = now + config_.n_cr_timeout;
  if (config_.block_size > 0 && --frames_left_in_block_ == 0) {
    frames_left_in_block_ = config_.block_size;
    result.flow_control = flow_control(IsoTpFlowStatus::continue_to_send);
  }
}

IsoTpReceiveResult IsoTpReceiver::on_timer(base::SimTime now) {
  IsoTpReceiveResult result;
  if (state_ == State::receiving && now >= consecutive_frame_deadline_) {
    drop(IsoTpReceiveError::timeout, result);
  }
  return result;
}

std::optional<base::SimTime> IsoTpReceiver::deadline() const {
  switch (state_) {
    case State::idle:
      return std::nullopt;
    case State::receiving:
      return consecutive_frame_deadline_;
  }
  return std::nullopt;
}

void IsoTpReceiver::reset() {
  state_ = State::idle;
  buffer_ = Bytes();
  expected_length_ = 0;
}

void IsoTpReceiver::drop(IsoTpReceiveError error, IsoTpReceiveResult& result) {
  reset();
  count(error, result);
}

void IsoTpReceiver::count(IsoTpReceiveError error, IsoTpReceiveResult& result) {
  ++counter_of(counters_, error);
  if (!result.error) {
    result.error = error;
  }
}

CanFrame IsoTpReceiver::flow_control(IsoTpFlowStatus status) const {
  return make_flow_control_frame(config_.flow_control_id, status, config_.block_size,
                                 st_min_byte_, config_.pad_frames);
}

}  // namespace ldoem::protocol
