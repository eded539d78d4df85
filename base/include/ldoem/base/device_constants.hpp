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

// Spec 6: the head turns at 5..20 Hz (TRANS_ROTATE, the configured motor speed).
inline constexpr std::uint16_t kMinMotorSpeedHz = 5;
inline constexpr std::uint16_t kMaxMotorSpeedHz = 20;

// Spec 5 (S1's rules, LD manual p. 22): TRANS_MEASURE refuses a sector table whose pulse
// frequency, (5760 / angle step) * motor speed, or its mean over the measuring sectors, is above
// these; the scan tool plans within them.
inline constexpr std::uint32_t kMaxPulseFrequencyHz = 14400;
inline constexpr std::uint32_t kMaxMeanPulseFrequencyHz = 10800;

}  // namespace ldoem::base
