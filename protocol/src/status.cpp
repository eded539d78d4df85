#include "ldoem/protocol/status.hpp"

namespace ldoem::protocol {

bool StatusByte::is_known() const {
  const bool sensor_known = sensor == SensorMode::idle || sensor == SensorMode::rotate ||
                            sensor == SensorMode::measure || sensor == SensorMode::error;
  const bool motor_known = motor == MotorMode::ok || motor == MotorMode::spin_too_low ||
                           motor == MotorMode::spin_too_high || motor == MotorMode::fault;
  return sensor_known && motor_known;
}

void append_status_block(Bytes& out, const StatusBlock& block) {
  out.insert(out.end(), block.unpublished.begin(), block.unpublished.end());
  out.push_back(block.status.to_byte());
}

StatusBlock read_status_block(ByteView bytes, std::size_t offset) {
  StatusBlock block;
  for (std::size_t i = 0; i < block.unpublished.size(); ++i) block.unpublished[i] = bytes[offset + i];
  block.status = StatusByte::from_byte(bytes[offset + 3]);
  return block;
}

}  // namespace ldoem::protocol
