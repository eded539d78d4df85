// One host's CAN identifier pair (D1). Each pair is its own ConnectionId on the CAN endpoint.
#pragma once

#include <cstdint>

namespace ldoem::endpoints {

struct CanIdPair {
  std::uint16_t request_id = 0x6C0;   // host -> LD
  std::uint16_t response_id = 0x6C1;  // LD -> host
  bool operator==(const CanIdPair&) const = default;
};

}  // namespace ldoem::endpoints
