// The one endpoint grammar (docs/endpoints.md): every program's transport options, the hub's
// config and a scene's `scanners:` list write a transport the same way, and this is the one
// parser. The daemon OFFERS an endpoint (it listens, makes the pty, owns the gpio lines); a host
// tool CONNECTS to one; EndpointUse says which, and which kind the option takes, so that the
// error can name what was expected. parse_endpoint is pure; opening happens in the emulator's
// io/ and the driver's transports.
//
//   can:IFACE                    D1 ids 0x6C0 / 0x6C1 (the daemon: its flash's ids)
//   can:IFACE:REQ:RESP           11-bit ids in hex; the daemon takes --can once per id pair
//   can:isotp:IFACE[:REQ:RESP]   host only: the kernel's CAN_ISOTP socket
//   tcp:HOST[:PORT]              port 49152 (spec 4.1); offer: 0 = any free port; HOST may be [v6]
//   serial:pty:PATH              offer: a pty symlinked at PATH; connect: the same as serial:PATH
//   serial:PATH[:BAUD]           host only: BAUD one of 4800 ... 115200 [115200] (spec 3.4)
//   lpt:pty:PATH                 each byte is the data register (D8); offer: symlinked at PATH
//   lpt:gpio:CHIP                libgpiod lines DIR/CLK/MODE of CHIP (label, name, path, number)
//   lpt:/dev/parportN            host only: a real port through ppdev
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::base {

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
  // The ids were written: the daemon then serves them instead of its flash's.
  bool ids_given = false;
  bool operator==(const CanEndpoint&) const = default;
};

struct TcpEndpoint {
  std::string host;  // name or address literal, without brackets
  std::uint16_t port = kHostTcpPort;  // offer side: 0 = any free port
  bool operator==(const TcpEndpoint&) const = default;
};

struct SerialEndpoint {
  std::string path;
  std::uint32_t baud = kDefaultSerialBaud;
  bool pty = false;  // written `serial:pty:PATH`
  bool operator==(const SerialEndpoint&) const = default;
};

enum class LptBackend : std::uint8_t { ppdev, pty, gpio };

struct LptEndpoint {
  LptBackend backend = LptBackend::ppdev;
  std::string target;  // device path (ppdev, pty) or chip (gpio)
  bool operator==(const LptEndpoint&) const = default;
};

using Endpoint = std::variant<CanEndpoint, TcpEndpoint, SerialEndpoint, LptEndpoint>;

enum class EndpointSide : std::uint8_t {
  offer,    // ldoem-emud, ldoem-replay, a scene's scanners: list
  connect,  // ldoem-scan, ldoem-hub, ldoem-conformance, the Python module
};

// What an option takes: one kind, or any transport that carries telegrams (--device).
enum class EndpointExpect : std::uint8_t { any, scanner, can, tcp, serial, lpt };

struct EndpointUse {
  EndpointSide side = EndpointSide::connect;
  EndpointExpect expect = EndpointExpect::any;
};

enum class EndpointErrorKind : std::uint8_t {
  empty,             // nothing to parse
  unknown_scheme,    // not can:, tcp:, serial:, lpt:
  missing_field,     // e.g. `can:`, `tcp:`, `lpt:pty:`
  surplus_field,     // more `:` fields than the grammar has
  bad_number,        // not a number where one is needed
  out_of_range,      // CAN id above 0x7FF, port 0 (connect) or above 65535, equal CAN ids, ...
  unsupported_baud,  // serial speed not in spec 3.4's list
  bad_name,          // CAN interface name longer than 15 characters
  wrong_kind,        // a well-formed endpoint of another kind than the option takes
  wrong_side,        // a form only the other side has (lpt:/dev/parport0 offered, ...)
  old_spelling,      // the spelling before docs/endpoints.md; `suggestion` is the new one
};

struct EndpointError {
  EndpointErrorKind kind = EndpointErrorKind::empty;
  std::string text;        // the string that was parsed
  std::string detail;      // which field, e.g. "CAN request id `800` is above 0x7FF"
  std::string suggestion;  // old_spelling: the text to write instead
  bool operator==(const EndpointError&) const = default;
};

// One line: "endpoint `can:vcan0:800:6C1`: out of range: CAN request id `800` is above 0x7FF".
std::string describe(const EndpointError& error);

// The line a tool prints for `option text` (without its program name):
// "--tcp 127.0.0.1:1 is the old spelling; write --tcp tcp:127.0.0.1:1 (docs/endpoints.md)", or
// "--device: endpoint `udp:x`: unknown scheme: ...". Every problem names the option first.
std::string describe_for_option(std::string_view option, const EndpointError& error);

Expected<Endpoint, EndpointError> parse_endpoint(std::string_view text, EndpointUse use = {});

// The canonical text: parse_endpoint(to_string(e), use) == e for every e that `use` parsed.
// Defaults are left out (CAN ids when not given, the serial speed when 115200) except the TCP
// port, which is always written.
std::string to_string(const Endpoint& endpoint);

// What a failed socket(PF_CAN, ...) with EAFNOSUPPORT means and what to do: one sentence for
// the daemon's and the driver's errors.
std::string can_unsupported_hint();

}  // namespace ldoem::base
