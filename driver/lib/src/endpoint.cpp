#include "ldoem/driver/endpoint.hpp"

#include <array>
#include <optional>
#include <vector>

#include "ldoem/base/numbers.hpp"

namespace ldoem::driver {
namespace {

using base::Expected;
using base::Unexpected;

constexpr std::size_t kMaxInterfaceNameChars = 15;  // IFNAMSIZ - 1 (Linux)
constexpr std::uint32_t kMaxStandardCanId = 0x7FF;  // D1: 11-bit identifiers
// Spec 3.4: the RS-232 baud codes 1..6.
constexpr std::array<std::uint32_t, 6> kSerialBauds{4800, 9600, 19200, 38400, 57600, 115200};

Unexpected<EndpointError> error(EndpointErrorKind kind, std::string_view text, std::string detail) {
  return Unexpected(EndpointError{kind, std::string(text), std::move(detail)});
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

std::optional<std::uint64_t> parse_hex_id(std::string_view field) {
  if (field.size() > 2 && field[0] == '0' && (field[1] == 'x' || field[1] == 'X')) {
    field.remove_prefix(2);
  }
  if (field.size() > 8) {
    return std::nullopt;
  }
  return base::parse_integer<std::uint64_t>(field, 16);
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

Expected<Endpoint, EndpointError> parse_can(std::string_view text, std::string_view rest) {
  std::vector<std::string_view> fields = split_fields(rest);
  CanEndpoint can;
  if (fields.size() >= 2 && fields[0] == "isotp") {
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
  }
  return Endpoint{can};
}

Expected<Endpoint, EndpointError> parse_tcp(std::string_view text, std::string_view rest) {
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
    const auto port = base::parse_integer<std::uint32_t>(port_field);
    if (!port) {
      return error(EndpointErrorKind::bad_number, text, "port `" + std::string(port_field) + "` is not a number");
    }
    if (*port == 0 || *port > 65535) {
      return error(EndpointErrorKind::out_of_range, text, "port must be 1..65535");
    }
    tcp.port = static_cast<std::uint16_t>(*port);
  }
  return Endpoint{tcp};
}

bool all_digits(std::string_view field) {
  if (field.empty()) {
    return false;
  }
  for (char c : field) {
    if (c < '0' || c > '9') {
      return false;
    }
  }
  return true;
}

Expected<Endpoint, EndpointError> parse_serial(std::string_view text, std::string_view rest) {
  if (rest.starts_with("pty:")) {
    rest.remove_prefix(4);
  }
  SerialEndpoint serial;
  std::string_view path = rest;
  // A trailing all-digit field is the speed; paths may hold ':' otherwise.
  const std::size_t colon = rest.rfind(':');
  if (colon != std::string_view::npos && all_digits(rest.substr(colon + 1))) {
    path = rest.substr(0, colon);
    const auto baud = base::parse_integer<std::uint32_t>(rest.substr(colon + 1));
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
  serial.path = std::string(path);
  return Endpoint{serial};
}

Expected<Endpoint, EndpointError> parse_lpt(std::string_view text, std::string_view rest) {
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
  lpt.target = std::string(rest);
  return Endpoint{lpt};
}

}  // namespace

std::string describe(const EndpointError& error) {
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
  }
  if (!error.detail.empty()) {
    line += ": " + error.detail;
  }
  return line;
}

base::Expected<Endpoint, EndpointError> parse_endpoint(std::string_view text) {
  if (text.empty()) {
    return error(EndpointErrorKind::empty, text, "expected can:, tcp:, serial: or lpt:");
  }
  const std::size_t colon = text.find(':');
  const std::string_view scheme = text.substr(0, colon);
  const std::string_view rest = colon == std::string_view::npos ? std::string_view{} : text.substr(colon + 1);
  if (scheme == "can") {
    return parse_can(text, rest);
  }
  if (scheme == "tcp") {
    return parse_tcp(text, rest);
  }
  if (scheme == "serial") {
    return parse_serial(text, rest);
  }
  if (scheme == "lpt") {
    return parse_lpt(text, rest);
  }
  return error(EndpointErrorKind::unknown_scheme, text, "expected can:, tcp:, serial: or lpt:");
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
    if (can.request_id != kDefaultCanRequestId || can.response_id != kDefaultCanResponseId) {
      text += ":" + hex_id(can.request_id) + ":" + hex_id(can.response_id);
    }
    return text;
  }
  std::string operator()(const TcpEndpoint& tcp) const {
    const bool v6 = tcp.host.find(':') != std::string::npos;
    return "tcp:" + (v6 ? "[" + tcp.host + "]" : tcp.host) + ":" + std::to_string(tcp.port);
  }
  std::string operator()(const SerialEndpoint& serial) const {
    return "serial:" + serial.path + ":" + std::to_string(serial.baud);
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

std::string format_endpoint(const Endpoint& endpoint) { return std::visit(Formatter{}, endpoint); }

}  // namespace ldoem::driver
