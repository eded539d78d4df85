// Ethernet/TCP framing (spec 4.1).
#include "ldoem/protocol/tcp_framing.hpp"

#include <algorithm>

namespace ldoem::protocol {

std::uint8_t xor_checksum(ByteView payload) {
  std::uint8_t checksum = 0;
  for (const auto byte : payload) checksum ^= byte;
  return checksum;
}

base::Expected<std::size_t, DecodeError> encode_tcp_frame_into(ByteView payload, std::span<std::uint8_t> out) {
  const std::size_t size = tcp_frame_size(payload.size());
  if (out.size() < size || payload.size() > UINT32_MAX) return base::Unexpected(DecodeError::too_large);
  auto cursor = std::copy(kTcpMagic.begin(), kTcpMagic.end(), out.begin());
  const auto length = static_cast<std::uint32_t>(payload.size());
  for (int shift = 24; shift >= 0; shift -= 8) *cursor++ = static_cast<std::uint8_t>(length >> shift);
  cursor = std::copy(payload.begin(), payload.end(), cursor);
  *cursor = xor_checksum(payload);
  return size;
}

Bytes encode_tcp_frame(ByteView payload) {
  Bytes frame(tcp_frame_size(payload.size()));
  const auto used = encode_tcp_frame_into(payload, frame);
  frame.resize(used.value_or(0));
  return frame;
}

TcpDeframer::TcpDeframer(std::size_t max_payload, TcpResync resync) : max_payload_(max_payload), resync_(resync) {}

void TcpDeframer::reset() {
  state_ = State::hunting;
  magic_matched_ = 0;
  length_bytes_ = 0;
  length_ = 0;
  payload_.clear();
}

std::vector<DeframerEvent> TcpDeframer::feed(ByteView chunk) {
  std::vector<DeframerEvent> events;
  for (const auto byte : chunk) {
    consume(byte, events);
    replay(events);
  }
  return events;
}

std::vector<DeframerEvent> TcpDeframer::abandon_frame() {
  std::vector<DeframerEvent> events;
  if (state_ == State::hunting) {
    skipped_bytes_ += magic_matched_;  // a partial magic is garbage, not a frame
    magic_matched_ = 0;
    return events;
  }
  const std::uint16_t code = payload_.size() >= 2 ? read_word_be(payload_, 0) : std::uint16_t{0};
  const TcpResync kept = resync_;
  resync_ = TcpResync::rescan_dropped;
  drop(FramingError{DecodeError::truncated, code}, events, std::nullopt);
  resync_ = kept;
  replay(events);
  return events;
}

// Bytes of dropped frames go through consume() again, oldest first, before any newer byte.
void TcpDeframer::replay(std::vector<DeframerEvent>& events) {
  while (!replay_.empty()) {
    const std::uint8_t byte = replay_.front();
    replay_.pop_front();
    consume(byte, events);
  }
}

// Searches for 02 55 53 50. Only the first magic byte (STX) can restart a partial match,
// because it does not occur again inside the magic.
void TcpDeframer::hunt(std::uint8_t byte) {
  if (byte == kTcpMagic[magic_matched_]) {
    ++magic_matched_;
  } else {
    skipped_bytes_ += magic_matched_;
    magic_matched_ = byte == kTcpMagic[0] ? 1 : 0;
    if (magic_matched_ == 0) ++skipped_bytes_;
  }
  if (magic_matched_ == kTcpMagic.size()) {
    magic_matched_ = 0;
    state_ = State::length;
    length_bytes_ = 0;
    length_ = 0;
  }
}

void TcpDeframer::drop(FramingError error, std::vector<DeframerEvent>& events, std::optional<std::uint8_t> last_byte) {
  ++dropped_frames_;
  events.emplace_back(error);
  if (resync_ == TcpResync::rescan_dropped) {
    // The frame's bytes after its magic, in order, ahead of any byte still waiting for replay:
    // the length bytes read so far, the payload, and the byte that showed the error.
    Bytes again;
    again.reserve(length_bytes_ + payload_.size() + 1);
    for (std::size_t i = 0; i < length_bytes_; ++i) {
      again.push_back(static_cast<std::uint8_t>(length_ >> (8 * (length_bytes_ - 1 - i))));
    }
    again.insert(again.end(), payload_.begin(), payload_.end());
    if (last_byte) again.push_back(*last_byte);
    replay_.insert(replay_.begin(), again.begin(), again.end());
  }
  reset();
}

void TcpDeframer::consume(std::uint8_t byte, std::vector<DeframerEvent>& events) {
  switch (state_) {
    case State::hunting:
      hunt(byte);
      return;
    case State::length:
      length_ = (length_ << 8) | byte;
      if (++length_bytes_ < 4) return;
      if (length_ > max_payload_) {
        drop(FramingError{DecodeError::too_large, 0}, events, std::nullopt);
        return;
      }
      payload_.clear();
      payload_.reserve(length_);
      state_ = length_ == 0 ? State::checksum : State::payload;
      return;
    case State::payload:
      payload_.push_back(byte);
      if (payload_.size() == length_) state_ = State::checksum;
      return;
    case State::checksum: {
      if (byte != xor_checksum(payload_)) {
        const std::uint16_t code = payload_.size() >= 2 ? read_word_be(payload_, 0) : std::uint16_t{0};
        drop(FramingError{DecodeError::bad_checksum, code}, events, byte);
        return;
      }
      events.emplace_back(Telegram{std::move(payload_)});
      reset();
      return;
    }
  }
}

}  // namespace ldoem::protocol
