// Endpoint strings: the one place where a user's `can:vcan0` or `lpt:pty:/tmp/ldoem-lpt`
// becomes a typed value (design.md convention 2). parse_endpoint is pure; opening happens in
// open_transport (transport.hpp) and open_lpt_port (lpt_port.hpp).
//
// Grammar (examples are rows of the test table in tests/driver/endpoint_test.cpp):
//   can:IFACE                     ISO-TP over CAN_RAW, D1 ids 0x6C0 request / 0x6C1 response
//   can:IFACE:REQ:RESP            the same with 11-bit ids in hex (`can:vcan0:6C0:6C1`)
//   can:isotp:IFACE[:REQ:RESP]    the kernel's CAN_ISOTP socket instead of the user-space one
//   tcp:HOST[:PORT]               default port 49152 (spec 4.1); HOST may be `[v6 literal]`
//   serial:PATH[:BAUD]            default 115200 (S2); BAUD one of 4800 ... 115200 (spec 3.4)
//   serial:pty:PATH[:BAUD]        the same; `pty:` only says the path is a pseudo terminal
//   lpt:/dev/parportN             real port through ppdev (D8)
//   lpt:pty:PATH                  each byte written is the new data register value (D8)
//   lpt:gpio:CHIP                 libgpiod lines DIR/CLK/MODE (or offsets 0/1/2) of CHIP
//                                 (label, name, path or number)
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::driver {

// D1 defaults.
inline constexpr std::uint32_t kDefaultCanRequestId = 0x6C0;
inline constexpr std::uint32_t kDefaultCanResponseId = 0x6C1;
// S2's default line speed (spec 4.2).
inline constexpr std::uint32_t kDefaultSerialBaud = 115200;

struct CanEndpoint {
  std::string interface;
  std::uint32_t request_id = kDefaultCanRequestId;
  std::uint32_t response_id = kDefaultCanResponseId;
  bool kernel_isotp = false;  // `can:isotp:...`
  bool operator==(const CanEndpoint&) const = default;
};

struct TcpEndpoint {
  std::string host;  // name or address literal, without brackets
  std::uint16_t port = base::kHostTcpPort;
  bool operator==(const TcpEndpoint&) const = default;
};

struct SerialEndpoint {
  std::string path;
  std::uint32_t baud = kDefaultSerialBaud;
  bool operator==(const SerialEndpoint&) const = default;
};

enum class LptBackend : std::uint8_t { ppdev, pty, gpio };

struct LptEndpoint {
  LptBackend backend = LptBackend::ppdev;
  std::string target;  // device path (ppdev, pty) or chip (gpio)
  bool operator==(const LptEndpoint&) const = default;
};

using Endpoint = std::variant<CanEndpoint, TcpEndpoint, SerialEndpoint, LptEndpoint>;

enum class EndpointErrorKind : std::uint8_t {
  empty,            // nothing to parse
  unknown_scheme,   // not can:, tcp:, serial:, lpt:
  missing_field,    // e.g. `can:`, `tcp:`, `lpt:pty:`
  surplus_field,    // more `:` fields than the grammar has
  bad_number,       // not a number where one is needed
  out_of_range,     // CAN id above 0x7FF, port 0 or above 65535, equal CAN ids, ...
  unsupported_baud, // serial speed not in spec 3.4's list
  bad_name,         // CAN interface name longer than 15 characters
};

struct EndpointError {
  EndpointErrorKind kind = EndpointErrorKind::empty;
  std::string text;    // the string that was parsed
  std::string detail;  // which field, e.g. "CAN request id `800` is above 0x7FF"
  bool operator==(const EndpointError&) const = default;
};

// One line: "endpoint `can:vcan0:800:6C1`: out of range: CAN request id `800` is above 0x7FF".
std::string describe(const EndpointError& error);

base::Expected<Endpoint, EndpointError> parse_endpoint(std::string_view text);

// The canonical text of an endpoint (parse_endpoint(format_endpoint(e)) == e); used as the
// `object` of every DriverError about it.
std::string format_endpoint(const Endpoint& endpoint);

}  // namespace ldoem::driver
