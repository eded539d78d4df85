// D11 device faults as the control unit sees them: the motor conditions that change the status
// nibble and lead to ERROR, and the beam faults that change ranges. The fault scheduler
// (emulator/faults) decides when; these types say what. Values only, no I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "ldoem/base/sim_time.hpp"
#include "ldoem/protocol/status.hpp"

namespace ldoem::control {

using base::SimTime;

// D11: motor_stall, motor_overspeed, encoder_error.
enum class MotorFault : std::uint8_t { stall, overspeed, encoder };

// One step of a motor fault's course: at `at` the motor nibble becomes `nibble` and/or the
// sensor mode becomes ERROR.
struct MotorFaultStep {
  SimTime at{};
  std::optional<protocol::MotorMode> nibble;
  bool enter_error = false;
  bool operator==(const MotorFaultStep&) const = default;
};

// `blind`: beams in the sector [from, to) (1/16 deg, wrapping through 0 when from > to), or a
// fraction of all beams chosen per (seed, revolution, beam), return no echo (DISTANCE 0, ECHO 0).
struct BlindFault {
  std::optional<std::uint16_t> from_ticks;
  std::optional<std::uint16_t> to_ticks;
  double fraction = 0.0;
  bool operator==(const BlindFault&) const = default;
};

// Every active beam fault. window_dirt is the share of received power lost: ECHO is scaled by
// (1 - window_dirt) and a return whose scaled ECHO falls below 1000 (D6: ECHO = 1000 I / I_min,
// so 1000 is the detection threshold) is dropped, far and dark targets first.
struct BeamFaults {
  std::vector<BlindFault> blind;
  double window_dirt = 0.0;
  std::uint64_t seed = 0;
  bool empty() const { return blind.empty() && window_dirt == 0.0; }
  bool operator==(const BeamFaults&) const = default;
};

// The nibble a motor fault shows once the head has given up (D11: stall stopped 0xB,
// overspeed 0x9, encoder 0xB).
protocol::MotorMode settled_nibble(MotorFault fault);

// True when the beam at angle_ticks is inside the sector [from, to) (wrapping through 0).
bool in_sector(std::uint16_t angle_ticks, std::uint16_t from_ticks, std::uint16_t to_ticks);

}  // namespace ldoem::control
