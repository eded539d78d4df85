// Typed errors of every decoder in protocol/ and the D2 failure reasons the LD answers with.
// A caller branches on these values, never on text (design.md convention 5).
#pragma once

#include <cstdint>
#include <string_view>

namespace ldoem::protocol {

// What was wrong with the bytes a decoder was given. "Need more bytes" is not an error: the
// streaming decoders simply return nothing until a telegram is complete.
enum class DecodeError : std::uint8_t {
  truncated,           // fewer bytes than the layout needs (or a telegram cut short)
  bad_length,          // a length field or the telegram length does not match the layout
  unknown_service,     // service code not in spec 3.2
  unpublished_layout,  // known service code whose payload layout nobody published (D2)
  unknown_config_key,  // SET_CONFIG / GET_CONFIG key without a published layout (spec 3.4)
  bad_header,          // TCP header magic is not 02 55 53 50 (spec 4.1)
  bad_checksum,        // TCP XOR checksum mismatch (spec 4.1)
  bad_hex,             // serial body holds a character that is not a hex digit (spec 4.2)
  bad_crc,             // serial CRC-16 mismatch (spec 4.2)
  out_of_range,        // a parameter value outside its published set
  too_large,           // telegram longer than the configured maximum (D3: 5816 bytes)
  bad_sequence,        // segment / package counter out of order (D1, spec 4.2)
  unexpected_frame,    // a frame or package that cannot occur in the current state
  bad_flow_control,    // ISO-TP flow-control frame with an invalid flag (D1)
  overflow,            // ISO-TP receiver signalled overflow (D1)
  timeout,             // a reassembly did not complete in time (D1: N_Bs, N_Cr)
  bad_text,            // text form of a telegram does not follow the grammar of text.hpp
};

// One line, lowercase, no trailing period: suitable for logs and test messages.
std::string_view describe(DecodeError error);

// D2: the REASON word of a SERVICE_FAILURE reply `FF 00 | REQUEST_CODE | REASON`.
enum class FailureReason : std::uint16_t {
  unknown_service = 0x0001,  // unknown service code, or a layout nobody published
  wrong_length = 0x0002,     // missing or surplus parameter WORDs
  wrong_state = 0x0003,      // not allowed in the current state (spec 5 with D2's entries)
  out_of_range = 0x0004,     // parameter out of range
  framing = 0x0005,          // TCP bad header/checksum, serial bad CRC/hex
  flash_not_stored = 0x0006, // the flash write failed; nothing changed (ours, L-flash-1)
};

std::string_view describe(FailureReason reason);

// The D2 reason that answers a framing-level error (TCP/serial deframers). Every deframer error
// is a framing error (reason 5) except a serial length mismatch, which is a wrong length.
FailureReason failure_reason_for_framing(DecodeError error);

}  // namespace ldoem::protocol
