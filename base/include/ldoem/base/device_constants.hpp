// Facts of the LD-OEM that both sides of the wire need (the daemon plays the device, the driver
// talks to it), named once. Everything else about the protocol lives in protocol/.
#pragma once

#include <cstdint>

namespace ldoem::base {

// Spec 2.3, 3.6, 6: the head's encoder counts 5760 ticks per turn, 1/16 degree each. Sector
// stops, angle steps and profile angles are all in these ticks.
inline constexpr std::uint32_t kTicksPerTurn = 5760;
inline constexpr std::uint32_t kTicksPerDegree = 16;
static_assert(kTicksPerTurn == 360 * kTicksPerDegree);

// Spec 4.1: over Ethernet the LD is the TCP server on this port.
inline constexpr std::uint16_t kHostTcpPort = 49152;

}  // namespace ldoem::base
