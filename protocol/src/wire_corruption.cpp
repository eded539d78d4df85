#include "ldoem/protocol/wire_corruption.hpp"

#include <optional>

#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace ldoem::protocol {
namespace {

constexpr std::size_t kCrcDigits = 4;

std::optional<std::uint8_t> hex_digit_value(std::uint8_t character) {
  if (character >= '0' && character <= '9') return static_cast<std::uint8_t>(character - '0');
  if (character >= 'a' && character <= 'f') return static_cast<std::uint8_t>(character - 'a' + 10);
  if (character >= 'A' && character <= 'F') return static_cast<std::uint8_t>(character - 'A' + 10);
  return std::nullopt;
}

}  // namespace

bool corrupt_tcp_checksum(std::span<std::uint8_t> frame) {
  if (frame.size() < kTcpHeaderSize + kTcpTrailerSize) return false;
  frame.back() ^= 0xFF;
  return true;
}

bool corrupt_serial_crc(std::span<std::uint8_t> package) {
  // STX, at least one WORD before the CRC, the CRC, ETX.
  if (package.size() < 2 + 2 * kCrcDigits || package.front() != kSerialStx || package.back() != kSerialEtx) {
    return false;
  }
  const std::span<std::uint8_t> digits = package.subspan(package.size() - 1 - kCrcDigits, kCrcDigits);
  std::uint16_t crc = 0;
  for (const std::uint8_t digit : digits) {
    const auto value = hex_digit_value(digit);
    if (!value) return false;
    crc = static_cast<std::uint16_t>((crc << 4) | *value);
  }
  crc ^= 0xFFFF;
  constexpr char kLowerHex[] = "0123456789abcdef";
  for (std::size_t i = 0; i < kCrcDigits; ++i) {
    digits[i] = static_cast<std::uint8_t>(kLowerHex[(crc >> (12 - 4 * i)) & 0xF]);
  }
  return true;
}

}  // namespace ldoem::protocol
