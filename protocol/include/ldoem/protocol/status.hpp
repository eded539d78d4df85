// The sensor status byte and the 4-byte status block (spec 2.4, D3).
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::protocol {

// Low nibble of the status byte (spec 2.4).
enum class SensorMode : std::uint8_t { idle = 0x1, rotate = 0x2, measure = 0x3, error = 0x4 };

// High nibble of the status byte (spec 2.4). 0 is also reported with the motor stopped in IDLE.
enum class MotorMode : std::uint8_t { ok = 0x0, spin_too_low = 0x4, spin_too_high = 0x9, fault = 0xB };

// The motor nibble's name, one spelling for the hub's replies and the Python package: "ok",
// "spin_too_low", "spin_too_high", "fault"; "unknown" for a nibble the spec does not define.
constexpr std::string_view motor_mode_name(MotorMode mode) {
  switch (mode) {
    case MotorMode::ok: return "ok";
    case MotorMode::spin_too_low: return "spin_too_low";
    case MotorMode::spin_too_high: return "spin_too_high";
    case MotorMode::fault: return "fault";
  }
  return "unknown";
}

// The status byte. Decoding never fails: a real device's unlisted nibble is kept as its raw
// value so that it can be shown and re-encoded; is_known() tells whether it is in spec 2.4.
struct StatusByte {
  SensorMode sensor = SensorMode::idle;
  MotorMode motor = MotorMode::ok;

  static constexpr std::uint8_t kSensorMask = 0x0F;
  static constexpr unsigned kMotorShift = 4;

  constexpr std::uint8_t to_byte() const {
    return static_cast<std::uint8_t>((static_cast<unsigned>(motor) << kMotorShift) |
                                     (static_cast<unsigned>(sensor) & kSensorMask));
  }
  static constexpr StatusByte from_byte(std::uint8_t byte) {
    return StatusByte{static_cast<SensorMode>(byte & kSensorMask),
                      static_cast<MotorMode>(byte >> kMotorShift)};
  }
  bool is_known() const;
  bool operator==(const StatusByte&) const = default;
};

// The status block: two WORDs whose 4th byte is the status byte (spec 2.4). Bytes 0..2 are
// unpublished; the emulator sends 0x00 (D3). They are kept so that a device's reply re-encodes
// to the same bytes.
struct StatusBlock {
  static constexpr std::size_t kSizeBytes = 4;
  std::array<std::uint8_t, 3> unpublished{};  // D3: 0x00
  StatusByte status;

  bool operator==(const StatusBlock&) const = default;
};

constexpr StatusBlock make_status_block(SensorMode sensor, MotorMode motor) {
  return StatusBlock{{}, StatusByte{sensor, motor}};
}

void append_status_block(Bytes& out, const StatusBlock& block);
// Precondition: bytes.size() >= offset + 4.
StatusBlock read_status_block(ByteView bytes, std::size_t offset);

}  // namespace ldoem::protocol
