// Private helper: the low nibble of an ISO-TP frame's first byte (isotp.hpp's frame layouts),
// read by the receiver and written by the sender: a single frame's length, a first frame's length
// high bits, a consecutive frame's sequence number, a flow-control frame's status.
#pragma once

#include <cstdint>

namespace ldoem::protocol::detail {

inline constexpr std::uint8_t kPciLowNibble = 0x0F;

}  // namespace ldoem::protocol::detail
