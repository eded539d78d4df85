// Step pulses from pseudo-LPT register writes (D8).
#include "ldoem/protocol/lpt.hpp"

namespace ldoem::protocol {

StepEdgeDetector::StepEdgeDetector(std::uint8_t initial_register)
    : last_register_(initial_register) {}

std::optional<StepPulse> StepEdgeDetector::on_write(base::SimTime at, std::uint8_t register_value) {
  const LptRegister before = decode_lpt(last_register_);
  const LptRegister after = decode_lpt(register_value);
  last_register_ = register_value;
  if (before.clock_high || !after.clock_high) {
    return std::nullopt;  // no rising edge: level held, falling edge, or other bits changed
  }
  ++steps_seen_;
  return StepPulse{at, after.direction, after.mode};
}

}  // namespace ldoem::protocol
