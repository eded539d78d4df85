// What the streaming deframers (TCP spec 4.1, serial spec 4.2) hand to their caller.
#pragma once

#include <cstdint>
#include <variant>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/errors.hpp"

namespace ldoem::protocol {

// A complete telegram payload: service code WORD then parameters.
struct Telegram {
  Bytes payload;
  bool operator==(const Telegram&) const = default;
};

// A frame that was seen but dropped. request_code is the service WORD when the broken frame
// carried one (so the emulator can answer SERVICE_FAILURE reason 5 per D2), else 0.
struct FramingError {
  DecodeError detail = DecodeError::bad_header;
  std::uint16_t request_code = 0;
  bool operator==(const FramingError&) const = default;
};

using DeframerEvent = std::variant<Telegram, FramingError>;

}  // namespace ldoem::protocol
