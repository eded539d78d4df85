// Ethernet/TCP framing (spec 4.1).
#include "ldoem/protocol/tcp_framing.hpp"

#include <algorithm>

namespace ldoem::protocol {

std::uint8_t xor_checksum(ByteView payload) {
  std::uint8_t checksum = 0;
  for (const auto byte : payload) checksum ^= byte;
  return checksum;
}

Expected<std::size_t, DecodeError> encode_tcp_frame_into(ByteView payload, std::span<std::uint8_t> out) {
  const std::size_t size = tcp_frame_size(payload.size());
  if (out.size() < size || payload.size() > UINT32_MAX) return Unexpected(DecodeError::too_large);
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

TcpDeframer::TcpDeframer(std::size_t max_payload) : max_payload_(max_payload) {}

void TcpDeframer::reset() {
  state_ = State::hunting;
  magic_matched_ = 0;
  length_bytes_ = 0;
  length_ = 0;
  payload_.clear();
}

std::vector<DeframerEvent> TcpDeframer::feed(ByteView chunk) {
  std::vector<DeframerEvent> events;
  for (const auto byte : chunk) consume(byte, events);
  return events;
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

void TcpDeframer::drop(FramingError error, std::vector<DeframerEvent>& events) {
  ++dropped_frames_;
  events.emplace_back(error);
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
        drop(FramingError{DecodeError::too_large, 0}, events);
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
        drop(FramingError{DecodeError::bad_checksum, code}, events);
        return;
      }
      events.emplace_back(Telegram{std::move(payload_)});
      reset();
      return;
    }
  }
}

}  // namespace ldoem::protocol
