// The golden vectors of spec section 7 (tests/vectors/spec-section7.yaml), with each TCP frame
// reduced to its payload: the suite sends payloads through whatever transport it was given.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "byte_pattern.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::conformance {

// Which payload bytes a real device is known to send (spec 7.2, last column).
struct AssertedPositions {
  bool all = false;                    // every byte, and the exact length
  std::vector<std::size_t> positions;  // when !all: these payload offsets (length: at least)
  std::size_t senstat_hole_bytes = 0;  // "all except SENSTAT bytes 0-2": holes before the last byte
};

struct RequestVector {
  std::string name;
  Bytes payload;
};

struct ReplyVector {
  std::string name;
  Bytes payload;
  AssertedPositions asserted;

  BytePattern emulator_pattern() const;  // every byte (the emulator must be byte-exact, spec 7.2)
  BytePattern device_pattern() const;    // only the asserted positions
};

struct SerialVector {
  std::string name;
  std::string ascii;  // between STX and ETX
  Bytes telegram() const;  // STX ascii ETX, as written on the line
};

struct VectorTable {
  std::vector<RequestVector> tcp_requests;
  std::vector<ReplyVector> tcp_replies;
  std::vector<SerialVector> serial_requests;

  const RequestVector* request(std::string_view name) const;
  const ReplyVector* reply(std::string_view name) const;
  const SerialVector* serial(std::string_view name) const;
};

// The copy compiled into the binary (generated from tests/vectors at build time).
std::string_view embedded_vectors_yaml();

// Errors name the row: "tcp_replies[3].frame: checksum 0x12 does not match payload XOR 0x34".
base::Expected<VectorTable, std::string> load_vector_table(std::string_view yaml_text);

// "payload[0..1], payload[5]", "idem", "+ payload[6..7]", "all", "structure only",
// "all except SENSTAT bytes 0–2"; `previous` resolves "idem" and "+".
base::Expected<AssertedPositions, std::string> parse_asserted(std::string_view text,
                                                                   const AssertedPositions& previous);

}  // namespace ldoem::conformance
