// ISO-TP sender: SF, FF (32-bit escape above 4095 bytes), CF paced by the peer's flow control
// (block size, STmin, WAIT, overflow) and the N_Bs timeout (D1).
#include <algorithm>
#include <cassert>

#include "ldoem/protocol/isotp.hpp"
#include "isotp_pci.hpp"

namespace ldoem::protocol {

namespace {

constexpr std::size_t kShortFirstFrameDataBytes = 6;    // after 1H LL
constexpr std::size_t kEscapedFirstFrameDataBytes = 2;  // after 10 00 LL LL LL LL

CanFrame frame_from(std::uint32_t id, const Bytes& bytes) {
  CanFrame frame;
  frame.id = id;
  frame.length = static_cast<std::uint8_t>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), frame.data.begin());
  return frame;
}

}  // namespace

IsoTpSender::IsoTpSender(IsoTpSenderConfig config) : config_(config) {}

bool IsoTpSender::busy() const {
  switch (state_) {
    case State::idle:
    case State::done:
    case State::failed:
      return false;
    case State::sending:
    case State::waiting_for_flow_control:
      return true;
  }
  return false;
}

base::Expected<std::monostate, IsoTpSendError> IsoTpSender::start(base::SimTime now, ByteView message) {
  if (busy()) {
    return base::Unexpected(IsoTpSendError::busy);
  }
  if (message.empty()) {
    return base::Unexpected(IsoTpSendError::empty_message);
  }
  waits_in_a_row_ = 0;
  if (message.size() > kIsoTpMaxEscapedLength) {
    return base::Unexpected(IsoTpSendError::too_large);
  }
  message_.assign(message.begin(), message.end());
  next_offset_ = 0;
  next_sequence_ = 1;
  next_frame_due_ = now;
  last_consecutive_sent_.reset();
  error_.reset();
  state_ = State::sending;
  return std::monostate{};
}

IsoTpSendPoll IsoTpSender::poll(base::SimTime now) {
  IsoTpSendPoll result;
  switch (state_) {
    case State::idle:
    case State::done:
    case State::failed:
      break;
    case State::sending:
      send_due_frames(now, result.frames);
      break;
    case State::waiting_for_flow_control:
      if (now >= flow_control_deadline_) {
        fail(IsoTpSendError::timeout);
      }
      break;
  }
  result.deadline = deadline();
  return result;
}

void IsoTpSender::send_due_frames(base::SimTime now, std::vector<CanFrame>& out) {
  if (now < next_frame_due_) {
    return;
  }
  if (next_offset_ == 0) {
    out.push_back(next_first_or_single_frame());
    if (next_offset_ == message_.size()) {
      state_ = State::done;  // a single frame needs no flow control
    } else {
      wait_for_flow_control(now);
    }
    return;
  }
  while (state_ == State::sending && now >= next_frame_due_) {
    out.push_back(next_consecutive_frame());
    last_consecutive_sent_ = now;
    next_frame_due_ = now + peer_st_min_;
    if (next_offset_ == message_.size()) {
      state_ = State::done;
    } else if (peer_block_size_ > 0 && --frames_left_in_block_ == 0) {
      wait_for_flow_control(now);
    } else if (peer_st_min_ > base::SimTime::zero()) {
      break;  // one CF per call: the next one counts STmin from when this one really went out
    }
  }
}

CanFrame IsoTpSender::next_first_or_single_frame() {
  Bytes bytes;
  const std::size_t length = message_.size();
  std::size_t data_bytes = 0;
  if (length <= kIsoTpMaxSingleFrameBytes) {
    bytes.push_back(static_cast<std::uint8_t>(length));  // 0L
    data_bytes = length;
  } else if (length <= kIsoTpMaxShortFirstFrameLength) {
    append_word_be(bytes, static_cast<std::uint16_t>(0x1000 | length));  // 1H LL
    data_bytes = kShortFirstFrameDataBytes;
  } else {
    append_word_be(bytes, 0x1000);  // 10 00 then the 32-bit length
    append_u32_be(bytes, static_cast<std::uint32_t>(length));
    data_bytes = kEscapedFirstFrameDataBytes;
  }
  bytes.insert(bytes.end(), message_.begin(),
               message_.begin() + static_cast<std::ptrdiff_t>(data_bytes));
  next_offset_ = data_bytes;
  return finish_frame(frame_from(config_.data_id, bytes));
}

CanFrame IsoTpSender::next_consecutive_frame() {
  const std::size_t data_bytes =
      std::min(message_.size() - next_offset_, kIsoTpConsecutiveFrameBytes);
  Bytes bytes;
  bytes.push_back(static_cast<std::uint8_t>(0x20 | next_sequence_));
  const auto begin = message_.begin() + static_cast<std::ptrdiff_t>(next_offset_);
  bytes.insert(bytes.end(), begin, begin + static_cast<std::ptrdiff_t>(data_bytes));
  next_offset_ += data_bytes;
  next_sequence_ = static_cast<std::uint8_t>((next_sequence_ + 1) & detail::kPciLowNibble);  // 15 -> 0
  return finish_frame(frame_from(config_.data_id, bytes));
}

CanFrame IsoTpSender::finish_frame(CanFrame frame) const {
  if (config_.pad_frames) {
    std::fill(frame.data.begin() + frame.length, frame.data.end(), kIsoTpPaddingByte);
    frame.length = kCanMaxDataBytes;
  }
  return frame;
}

void IsoTpSender::wait_for_flow_control(base::SimTime now) {
  state_ = State::waiting_for_flow_control;
  flow_control_deadline_ = now + config_.n_bs_timeout;
}

void IsoTpSender::on_flow_control(base::SimTime now, const CanFrame& frame) {
  if (state_ != State::waiting_for_flow_control) {
    return;  // ISO 15765-2: an FC nobody waits for is ignored
  }
  if (now >= flow_control_deadline_) {
    fail(IsoTpSendError::timeout);
    return;
  }
  if (frame.length < kIsoTpFlowControlBytes || frame.length > kCanMaxDataBytes ||
      isotp_frame_type(frame) != IsoTpFrameType::flow_control) {
    return;
  }
  switch (frame.data[0] & detail::kPciLowNibble) {
    case static_cast<std::uint8_t>(IsoTpFlowStatus::continue_to_send):
      waits_in_a_row_ = 0;
      peer_block_size_ = frame.data[1];
      frames_left_in_block_ = peer_block_size_;
      peer_st_min_ = decode_st_min(frame.data[2]);
      // STmin separates any two CFs, also across a block boundary.
      next_frame_due_ = last_consecutive_sent_
                            ? std::max(now, *last_consecutive_sent_ + peer_st_min_)
                            : now;
      state_ = State::sending;
      return;
    case static_cast<std::uint8_t>(IsoTpFlowStatus::wait):
      if (++waits_in_a_row_ > config_.max_wait_frames) {
        fail(IsoTpSendError::too_many_waits);
        return;
      }
      flow_control_deadline_ = now + config_.n_bs_timeout;  // N_Bs starts again
      return;
    case static_cast<std::uint8_t>(IsoTpFlowStatus::overflow):
      fail(IsoTpSendError::overflow);
      return;
    default:
      fail(IsoTpSendError::invalid_flow_status);  // FS 3..15 are reserved
      return;
  }
}

std::optional<base::SimTime> IsoTpSender::deadline() const {
  switch (state_) {
    case State::idle:
    case State::done:
    case State::failed:
      return std::nullopt;
    case State::sending:
      return next_frame_due_;
    case State::waiting_for_flow_control:
      return flow_control_deadline_;
  }
  return std::nullopt;
}

void IsoTpSender::reset() {
  state_ = State::idle;
  error_.reset();
  message_ = Bytes();
  next_offset_ = 0;
}

void IsoTpSender::fail(IsoTpSendError error) {
  state_ = State::failed;
  error_ = error;
  message_ = Bytes();
}

}  // namespace ldoem::protocol
