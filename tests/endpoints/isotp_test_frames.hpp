// What the ISO-TP channel tests build their frames and payloads from.
#pragma once

#include <cstddef>
#include <cstdint>
#include <numeric>

#include "ldoem/protocol/can_frame.hpp"

namespace ldoem::endpoints::test {

inline protocol::CanFrame frame(std::uint32_t id, protocol::Bytes bytes) { return *protocol::make_can_frame(id, bytes); }

// 1, 2, 3, ...: a payload whose every byte says where it belongs.
inline protocol::Bytes counting_bytes(std::size_t count) {
  protocol::Bytes bytes(count);
  std::iota(bytes.begin(), bytes.end(), std::uint8_t{1});
  return bytes;
}

}  // namespace ldoem::endpoints::test
