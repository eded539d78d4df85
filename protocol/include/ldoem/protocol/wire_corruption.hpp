// The corrupted checksums of D11's corrupt_checksum fault, as pure functions on an encoded frame,
// so that the emulator writes them and a test computes them from one definition.
//   TCP (spec 4.1): the trailing XOR byte is inverted (XOR 0xFF): never the right value.
//   Serial (spec 4.2): the CRC WORD of one package is inverted (XOR 0xFFFF) and written back as
//   four lowercase hex digits, like every WORD we send.
#pragma once

#include <cstdint>
#include <span>

namespace ldoem::protocol {

// `frame` is one whole TCP frame (header to checksum). False when it is too short to be one.
bool corrupt_tcp_checksum(std::span<std::uint8_t> frame);

// `package` is one whole serial package, STX ... CCCC ETX. False when it is not one.
bool corrupt_serial_crc(std::span<std::uint8_t> package);

}  // namespace ldoem::protocol
