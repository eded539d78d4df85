// A classic CAN 2.0A data frame as protocol/ sees it (D1), independent of <linux/can.h>: the
// emulator's and the driver's SocketCAN edges convert to and from struct can_frame.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::protocol {

// D1: 11-bit identifiers, classic frames of at most 8 data bytes.
inline constexpr std::uint32_t kCanStandardIdMask = 0x7FF;
inline constexpr std::size_t kCanMaxDataBytes = 8;

struct CanFrame {
  std::uint32_t id = 0;     // 11-bit identifier (D1)
  std::uint8_t length = 0;  // DLC: number of data bytes used, 0..8
  std::array<std::uint8_t, kCanMaxDataBytes> data{};

  // The bytes the DLC covers. A length above 8 only arrives from a broken edge or a fuzzer;
  // the view is clamped so that it never reads past the array.
  ByteView payload() const {
    return ByteView(data.data(), length <= kCanMaxDataBytes ? length : kCanMaxDataBytes);
  }

  // Frames compare by the bytes the DLC covers: bytes past the DLC are not on the bus.
  friend bool operator==(const CanFrame& a, const CanFrame& b) {
    if (a.id != b.id || a.length != b.length) {
      return false;
    }
    const ByteView pa = a.payload();
    const ByteView pb = b.payload();
    for (std::size_t i = 0; i < pa.size(); ++i) {
      if (pa[i] != pb[i]) {
        return false;
      }
    }
    return true;
  }
};

// A frame holding `bytes`, or nothing when the identifier needs more than 11 bits or the bytes
// do not fit one classic frame.
inline std::optional<CanFrame> make_can_frame(std::uint32_t id, ByteView bytes) {
  if ((id & ~kCanStandardIdMask) != 0 || bytes.size() > kCanMaxDataBytes) {
    return std::nullopt;
  }
  CanFrame frame;
  frame.id = id;
  frame.length = static_cast<std::uint8_t>(bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    frame.data[i] = bytes[i];
  }
  return frame;
}

}  // namespace ldoem::protocol
