#include "ldoem/base/endpoint.hpp"

#include <array>
#include <optional>
#include <vector>

#include "ldoem/base/numbers.hpp"

namespace ldoem::base {
namespace {

constexpr std::size_t kMaxInterfaceNameChars = 15;  // IFNAMSIZ - 1 (Linux)
constexpr std::uint32_t kMaxStandardCanId = 0x7FF;  // D1: 11-bit identifiers
// Spec 3.4: the RS-232 baud codes 1..6.
constexpr std::array<std::uint32_t, 6> kSerialBauds{4800, 9600, 19200, 38400, 57600, 115200};

Unexpected<EndpointError> error(EndpointErrorKind kind, std::string_view text, std::string detail) {
  return Unexpected(EndpointError{kind, std::string(text), std::move(detail), {}});
}

std::vector<std::string_view> split_fields(std::string_view rest) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t colon = rest.find(':', start);
    if (colon == std::string_view::npos) {
      fields.push_back(rest.substr(start));
      return fields;
    }
    fields.push_back(rest.substr(start, colon - start));
    start = colon + 1;
  }
}

bool all_digits(std::string_view field) {
  return !field.empty() && field.find_first_not_of("0123456789") == std::string_view::npos;
}

std::optional<std::uint64_t> parse_hex_id(std::string_view field) {
  if (field.size() > 2 && field[0] == '0' && (field[1] == 'x' || field[1] == 'X')) {
    field.remove_prefix(2);
  }
  if (field.size() > 8) {
    return std::nullopt;
  }
  return parse_integer<std::uint64_t>(field, 16);
}

Expected<std::uint32_t, EndpointError> parse_can_id(std::string_view text, std::string_view field,
                                                    std::string_view which) {
  const auto id = parse_hex_id(field);
  if (!id) {
    return error(EndpointErrorKind::bad_number, text,
                 "CAN " + std::string(which) + " id `" + std::string(field) + "` is not hex");
  }
  if (*id > kMaxStandardCanId) {
    return error(EndpointErrorKind::out_of_range, text,
                 "CAN " + std::string(which) + " id `" + std::string(field) + "` is above 0x7FF");
  }
  return static_cast<std::uint32_t>(*id);
}

Expected<Endpoint, EndpointError> parse_can(std::string_view text, std::string_view rest, EndpointSide side) {
  std::vector<std::string_view> fields = split_fields(rest);
  CanEndpoint can;
  if (fields.size() >= 2 && fields[0] == "isotp") {
    if (side == EndpointSide::offer) {
      return error(EndpointErrorKind::wrong_side, text,
                   "can:isotp: is a host's kernel socket; ldoem-emud offers can:IFACE[:REQ:RESP]");
    }
    can.kernel_isotp = true;
    fields.erase(fields.begin());
  }
  if (fields[0].empty()) {
    return error(EndpointErrorKind::missing_field, text, "no CAN interface name");
  }
  if (fields[0].size() > kMaxInterfaceNameChars) {
    return error(EndpointErrorKind::bad_name, text, "CAN interface name longer than 15 characters");
  }
  can.interface = std::string(fields[0]);
  if (fields.size() == 2) {
    return error(EndpointErrorKind::missing_field, text, "a request id needs a response id");
  }
  if (fields.size() > 3) {
    return error(EndpointErrorKind::surplus_field, text, "expected can:IFACE[:REQ:RESP]");
  }
  if (fields.size() == 3) {
    auto request = parse_can_id(text, fields[1], "request");
    if (!request) {
      return Unexpected(request.error());
    }
    auto response = parse_can_id(text, fields[2], "response");
    if (!response) {
      return Unexpected(response.error());
    }
    if (*request == *response) {
      return error(EndpointErrorKind::out_of_range, text, "request and response ids must differ");
    }
    can.request_id = *request;
    can.response_id = *response;
    can.ids_given = true;
  }
  return Endpoint{can};
}

Expected<Endpoint, EndpointError> parse_tcp(std::string_view text, std::string_view rest, EndpointSide side) {
  TcpEndpoint tcp;
  std::string_view host = rest;
  std::string_view port_field;
  bool has_port = false;
  if (!rest.empty() && rest.front() == '[') {
    const std::size_t close = rest.find(']');
    if (close == std::string_view::npos) {
      return error(EndpointErrorKind::missing_field, text, "`[` without `]` around the address");
    }
    host = rest.substr(1, close - 1);
    std::string_view after = rest.substr(close + 1);
    if (!after.empty()) {
      if (after.front() != ':') {
        return error(EndpointErrorKind::surplus_field, text, "text after `]` must be `:PORT`");
      }
      port_field = after.substr(1);
      has_port = true;
    }
  } else {
    const std::size_t colon = rest.find(':');
    if (colon != std::string_view::npos) {
      host = rest.substr(0, colon);
      port_field = rest.substr(colon + 1);
      has_port = true;
      if (port_field.find(':') != std::string_view::npos) {
        return error(EndpointErrorKind::surplus_field, text, "expected tcp:HOST[:PORT]");
      }
    }
  }
  if (host.empty()) {
    return error(EndpointErrorKind::missing_field, text, "no host");
  }
  tcp.host = std::string(host);
  if (has_port) {
    const auto port = parse_integer<std::uint32_t>(port_field);
    if (!port) {
      return error(EndpointErrorKind::bad_number, text, "port `" + std::string(port_field) + "` is not a number");
    }
    // Port 0 asks the kernel for any free port: only a listener can do that.
    const bool offer = side == EndpointSide::offer;
    if ((*port == 0 && !offer) || *port > 65535) {
      return error(EndpointErrorKind::out_of_range, text,
                   offer ? "port must be 0..65535 (0: any free port)" : "port must be 1..65535");
    }
    tcp.port = static_cast<std::uint16_t>(*port);
  }
  return Endpoint{tcp};
}

Expected<Endpoint, EndpointError> parse_serial(std::string_view text, std::string_view rest, EndpointSide side) {
  SerialEndpoint serial;
  if (rest.starts_with("pty:")) {
    serial.pty = true;
    rest.remove_prefix(4);
  }
  std::string_view path = rest;
  // A trailing all-digit field is the speed; paths may hold ':' otherwise.
  const std::size_t colon = rest.rfind(':');
  if (colon != std::string_view::npos && all_digits(rest.substr(colon + 1))) {
    if (side == EndpointSide::offer) {
      return error(EndpointErrorKind::wrong_side, text,
                   "the line speed is the host's choice (spec 3.4); offer serial:pty:PATH");
    }
    path = rest.substr(0, colon);
    const auto baud = parse_integer<std::uint32_t>(rest.substr(colon + 1));
    bool listed = false;
    for (std::uint32_t known : kSerialBauds) {
      listed = listed || (baud && *baud == known);
    }
    if (!listed) {
      return error(EndpointErrorKind::unsupported_baud, text,
                   "baud `" + std::string(rest.substr(colon + 1)) +
                       "` is not one of 4800 9600 19200 38400 57600 115200");
    }
    serial.baud = *baud;
  }
  if (path.empty()) {
    return error(EndpointErrorKind::missing_field, text, "no device path");
  }
  if (side == EndpointSide::offer && !serial.pty) {
    return error(EndpointErrorKind::wrong_side, text,
                 "the emulator offers serial:pty:PATH (a pty symlinked at PATH), not a device");
  }
  serial.path = std::string(path);
  return Endpoint{serial};
}

Expected<Endpoint, EndpointError> parse_lpt(std::string_view text, std::string_view rest, EndpointSide side) {
  LptEndpoint lpt;
  if (rest.starts_with("pty:")) {
    lpt.backend = LptBackend::pty;
    rest.remove_prefix(4);
  } else if (rest.starts_with("gpio:")) {
    lpt.backend = LptBackend::gpio;
    rest.remove_prefix(5);
  }
  if (rest.empty()) {
    return error(EndpointErrorKind::missing_field, text,
                 lpt.backend == LptBackend::gpio ? "no gpio chip" : "no device path");
  }
  if (side == EndpointSide::offer && lpt.backend == LptBackend::ppdev) {
    return error(EndpointErrorKind::wrong_side, text,
                 "a parallel port is the host's; the emulator offers lpt:pty:PATH or lpt:gpio:CHIP");
  }
  lpt.target = std::string(rest);
  return Endpoint{lpt};
}

// The new text for a spelling from before the grammar (docs/endpoints.md), or nothing when
// `text` is not one: `127.0.0.1:49152` for a TCP option, `pty:/x` for --serial or --lpt, `vcan0`
// for --can, `/dev/ttyUSB0` for a serial device.
std::optional<std::string> old_spelling(std::string_view text, EndpointUse use) {
  const bool plain_name = text.size() <= kMaxInterfaceNameChars &&
                          text.find_first_of(":/.[") == std::string_view::npos;
  const std::size_t colon = text.rfind(':');
  const bool host_port = (colon == std::string_view::npos ? !text.empty() : colon > 0 && all_digits(text.substr(colon + 1))) &&
                         text.find('/') == std::string_view::npos && !text.starts_with("pty:") &&
                         !text.starts_with("gpio:");
  const std::string owned(text);
  switch (use.expect) {
    case EndpointExpect::lpt:
      if (text.starts_with("pty:") || text.starts_with("gpio:") || text.starts_with("/dev/")) return "lpt:" + owned;
      return std::nullopt;
    case EndpointExpect::serial:
      if (text.starts_with("pty:") || text.starts_with("/")) return "serial:" + owned;
      return std::nullopt;
    case EndpointExpect::tcp:
      if (all_digits(text)) return "tcp:127.0.0.1:" + owned;  // a scene's bare port
      if (host_port) return "tcp:" + owned;
      return std::nullopt;
    case EndpointExpect::can:
      if (plain_name) return "can:" + owned;
      return std::nullopt;
    case EndpointExpect::any:
    case EndpointExpect::scanner:
      if (text.starts_with("pty:") || text.starts_with("/")) return "serial:" + owned;
      if (plain_name && !all_digits(text)) return "can:" + owned;
      if (host_port && colon != std::string_view::npos) return "tcp:" + owned;
      return std::nullopt;
  }
  return std::nullopt;
}

std::string_view expected_forms(EndpointUse use) {
  const bool offer = use.side == EndpointSide::offer;
  switch (use.expect) {
    case EndpointExpect::can: return "expected can:IFACE[:REQ:RESP]";
    case EndpointExpect::tcp: return "expected tcp:HOST[:PORT]";
    case EndpointExpect::serial: return offer ? "expected serial:pty:PATH" : "expected serial:PATH[:BAUD]";
    case EndpointExpect::lpt: return offer ? "expected lpt:pty:PATH or lpt:gpio:CHIP" : "expected lpt:pty:PATH, lpt:gpio:CHIP or lpt:/dev/parportN";
    case EndpointExpect::scanner: return "expected can:, tcp: or serial:";
    case EndpointExpect::any: break;
  }
  return "expected can:, tcp:, serial: or lpt:";
}

bool kind_fits(const Endpoint& endpoint, EndpointExpect expect) {
  switch (expect) {
    case EndpointExpect::any: return true;
    case EndpointExpect::scanner: return !std::holds_alternative<LptEndpoint>(endpoint);
    case EndpointExpect::can: return std::holds_alternative<CanEndpoint>(endpoint);
    case EndpointExpect::tcp: return std::holds_alternative<TcpEndpoint>(endpoint);
    case EndpointExpect::serial: return std::holds_alternative<SerialEndpoint>(endpoint);
    case EndpointExpect::lpt: return std::holds_alternative<LptEndpoint>(endpoint);
  }
  return false;
}

}  // namespace

std::string describe(const EndpointError& error) {
  if (error.kind == EndpointErrorKind::old_spelling) {
    return "`" + error.text + "` is the old spelling; write " + error.suggestion + " (docs/endpoints.md)";
  }
  std::string line = "endpoint `" + error.text + "`: ";
  switch (error.kind) {
    case EndpointErrorKind::empty: line += "empty"; break;
    case EndpointErrorKind::unknown_scheme: line += "unknown scheme"; break;
    case EndpointErrorKind::missing_field: line += "missing field"; break;
    case EndpointErrorKind::surplus_field: line += "surplus field"; break;
    case EndpointErrorKind::bad_number: line += "bad number"; break;
    case EndpointErrorKind::out_of_range: line += "out of range"; break;
    case EndpointErrorKind::unsupported_baud: line += "unsupported baud rate"; break;
    case EndpointErrorKind::bad_name: line += "bad name"; break;
    case EndpointErrorKind::wrong_kind: line += "wrong kind"; break;
    case EndpointErrorKind::wrong_side: line += "wrong side"; break;
    case EndpointErrorKind::old_spelling: break;
  }
  if (!error.detail.empty()) {
    line += ": " + error.detail;
  }
  return line;
}

std::string describe_for_option(std::string_view option, const EndpointError& error) {
  const std::string name(option);
  if (error.kind == EndpointErrorKind::old_spelling) {
    return name + " " + error.text + " is the old spelling; write " + name + " " + error.suggestion +
           " (docs/endpoints.md)";
  }
  return name + ": " + describe(error);
}

Expected<Endpoint, EndpointError> parse_endpoint(std::string_view text, EndpointUse use) {
  if (text.empty()) {
    return error(EndpointErrorKind::empty, text, std::string(expected_forms(use)));
  }
  const std::size_t colon = text.find(':');
  const std::string_view scheme = text.substr(0, colon);
  const std::string_view rest = colon == std::string_view::npos ? std::string_view{} : text.substr(colon + 1);
  Expected<Endpoint, EndpointError> parsed = error(EndpointErrorKind::unknown_scheme, text, std::string(expected_forms(use)));
  if (scheme == "can") {
    parsed = parse_can(text, rest, use.side);
  } else if (scheme == "tcp") {
    parsed = parse_tcp(text, rest, use.side);
  } else if (scheme == "serial") {
    parsed = parse_serial(text, rest, use.side);
  } else if (scheme == "lpt") {
    parsed = parse_lpt(text, rest, use.side);
  } else if (auto suggestion = old_spelling(text, use)) {
    // Only a suggestion that parses is offered: it must not lead to a second error.
    if (parse_endpoint(*suggestion, use)) {
      return Unexpected(EndpointError{EndpointErrorKind::old_spelling, std::string(text), {}, std::move(*suggestion)});
    }
  }
  if (parsed && !kind_fits(*parsed, use.expect)) {
    return error(EndpointErrorKind::wrong_kind, text,
                 use.expect == EndpointExpect::scanner ? "an lpt: endpoint carries no telegrams; " + std::string(expected_forms(use))
                                                       : std::string(expected_forms(use)));
  }
  return parsed;
}

namespace {

std::string hex_id(std::uint32_t id) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  return std::string{kDigits[(id >> 8) & 0xF], kDigits[(id >> 4) & 0xF], kDigits[id & 0xF]};
}

struct Formatter {
  std::string operator()(const CanEndpoint& can) const {
    std::string text = can.kernel_isotp ? "can:isotp:" : "can:";
    text += can.interface;
    if (can.ids_given || can.request_id != kDefaultCanRequestId || can.response_id != kDefaultCanResponseId) {
      text += ":" + hex_id(can.request_id) + ":" + hex_id(can.response_id);
    }
    return text;
  }
  std::string operator()(const TcpEndpoint& tcp) const {
    // Brackets for a v6 literal, and for a name that would otherwise read as one.
    const bool bracket = tcp.host.find(':') != std::string::npos || tcp.host.starts_with("[");
    return "tcp:" + (bracket ? "[" + tcp.host + "]" : tcp.host) + ":" + std::to_string(tcp.port);
  }
  std::string operator()(const SerialEndpoint& serial) const {
    std::string text = std::string(serial.pty ? "serial:pty:" : "serial:") + serial.path;
    // A path ending in ":digits" would read as a speed without the explicit one.
    const std::size_t colon = serial.path.rfind(':');
    const bool ambiguous = colon != std::string::npos && all_digits(std::string_view(serial.path).substr(colon + 1));
    if (serial.baud != kDefaultSerialBaud || ambiguous) {
      text += ":" + std::to_string(serial.baud);
    }
    return text;
  }
  std::string operator()(const LptEndpoint& lpt) const {
    switch (lpt.backend) {
      case LptBackend::ppdev: return "lpt:" + lpt.target;
      case LptBackend::pty: return "lpt:pty:" + lpt.target;
      case LptBackend::gpio: return "lpt:gpio:" + lpt.target;
    }
    return "lpt:" + lpt.target;
  }
};

}  // namespace

std::string to_string(const Endpoint& endpoint) { return std::visit(Formatter{}, endpoint); }

std::string can_unsupported_hint() {
  return "this kernel has no CAN: load it with "
         "`modprobe vcan` (then `ip link add dev vcan0 type vcan && ip link set up vcan0`), run inside the "
         "UML harness (scripts/uml/, docs/uml-harness.md), or use tcp: or serial: (docs/endpoints.md)";
}

}  // namespace ldoem::base
