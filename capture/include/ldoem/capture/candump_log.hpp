// The log format of can-utils `candump -l` / `candump -L`, one frame per line:
//   (1700000000.123456) vcan0 6C0#0301000039FF
//   (1700000000.123789) vcan0 6C1#1016830139FF0001   [optional trailing " R" or " T" of newer can-utils]
// TIME is seconds with any number of fraction digits, the identifier is 3 hex digits (11 bit)
// or 8 (29 bit), the data up to 8 bytes as hex pairs; `123#R` is a remote frame and `123##F...`
// a CAN FD frame. Pure: the caller reads the file and hands over its text.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/protocol/can_frame.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::capture {

enum class CandumpError : std::uint8_t {
  bad_timestamp,   // no "(seconds.fraction)" at the start
  missing_field,   // interface or frame missing
  bad_identifier,  // not 3 or 8 hex digits, or above 0x7FF in the 3-digit form
  bad_data,        // odd number of hex digits, non-hex, or more than 8 bytes
  unsupported,     // CAN FD (##) or XL frames: not part of D1
};
std::string_view describe(CandumpError error);

struct CandumpFailure {
  CandumpError error = CandumpError::missing_field;
  std::size_t line = 0;  // 1-based
};

struct CandumpEntry {
  std::uint64_t time_ns = 0;
  std::string interface;
  protocol::CanFrame frame;
  bool extended_id = false;  // 29-bit identifier: kept, but not D1 traffic
  bool remote = false;       // RTR frame: no data
  bool operator==(const CandumpEntry&) const = default;
};

// One line (without the newline). Blank lines are the caller's business.
[[nodiscard]] base::Expected<CandumpEntry, CandumpError> parse_candump_line(std::string_view line);

// Every line of a log; blank lines and lines starting with '#' are skipped. The first bad line
// stops the parse and is reported with its number.
[[nodiscard]] base::Expected<std::vector<CandumpEntry>, CandumpFailure> parse_candump_log(std::string_view text);

// The line candump -l would print for a frame (11-bit identifiers only), e.g. for tests.
std::string format_candump_line(std::uint64_t time_ns, std::string_view interface, const protocol::CanFrame& frame);

// True when the text starts like a candump log: "(" then a digit.
bool looks_like_candump_log(std::string_view text);

}  // namespace ldoem::capture
