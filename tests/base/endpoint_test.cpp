// The endpoint grammar (base/endpoint.hpp, docs/endpoints.md): every form on both sides, the
// round trip through to_string, and every error message, old spellings included. The rows of
// docs/endpoints.md's table are rows here.
#include "ldoem/base/endpoint.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ldoem::base {
namespace {

constexpr EndpointUse kOffer{EndpointSide::offer, EndpointExpect::any};
constexpr EndpointUse kConnect{EndpointSide::connect, EndpointExpect::any};

struct GoodRow {
  std::string text;
  EndpointUse use;
  Endpoint expected;
};

std::vector<GoodRow> good_rows() {
  return {
      {"can:vcan0", kOffer, CanEndpoint{"vcan0", 0x6C0, 0x6C1, false, false}},
      {"can:vcan0", kConnect, CanEndpoint{"vcan0", 0x6C0, 0x6C1, false, false}},
      {"can:vcan0:6C2:6C3", kOffer, CanEndpoint{"vcan0", 0x6C2, 0x6C3, false, true}},
      {"can:vcan0:6C0:6C1", kConnect, CanEndpoint{"vcan0", 0x6C0, 0x6C1, false, true}},
      {"can:can1:0x123:7ff", kConnect, CanEndpoint{"can1", 0x123, 0x7FF, false, true}},
      {"can:isotp:vcan0", kConnect, CanEndpoint{"vcan0", 0x6C0, 0x6C1, true, false}},
      {"can:isotp:vcan0:100:101", kConnect, CanEndpoint{"vcan0", 0x100, 0x101, true, true}},
      {"tcp:127.0.0.1:49152", kOffer, TcpEndpoint{"127.0.0.1", 49152}},
      {"tcp:127.0.0.1", kOffer, TcpEndpoint{"127.0.0.1", 49152}},
      {"tcp:127.0.0.1:0", kOffer, TcpEndpoint{"127.0.0.1", 0}},
      {"tcp:scanner.lab:5000", kConnect, TcpEndpoint{"scanner.lab", 5000}},
      {"tcp:[::1]:49153", kConnect, TcpEndpoint{"::1", 49153}},
      {"tcp:[::1]", kOffer, TcpEndpoint{"::1", 49152}},
      {"serial:pty:/tmp/ldoem-serial", kOffer, SerialEndpoint{"/tmp/ldoem-serial", 115200, true}},
      {"serial:pty:/tmp/ldoem-serial", kConnect, SerialEndpoint{"/tmp/ldoem-serial", 115200, true}},
      {"serial:pty:/tmp/ldoem-serial:57600", kConnect, SerialEndpoint{"/tmp/ldoem-serial", 57600, true}},
      {"serial:/dev/ttyUSB0", kConnect, SerialEndpoint{"/dev/ttyUSB0", 115200, false}},
      {"serial:/dev/ttyS1:9600", kConnect, SerialEndpoint{"/dev/ttyS1", 9600, false}},
      {"lpt:pty:/tmp/ldoem-lpt", kOffer, LptEndpoint{LptBackend::pty, "/tmp/ldoem-lpt"}},
      {"lpt:pty:/tmp/ldoem-lpt", kConnect, LptEndpoint{LptBackend::pty, "/tmp/ldoem-lpt"}},
      {"lpt:gpio:ldoem-lpt", kOffer, LptEndpoint{LptBackend::gpio, "ldoem-lpt"}},
      {"lpt:gpio:gpiochip3", kConnect, LptEndpoint{LptBackend::gpio, "gpiochip3"}},
      {"lpt:/dev/parport0", kConnect, LptEndpoint{LptBackend::ppdev, "/dev/parport0"}},
  };
}

TEST(Endpoint, EveryForm_ParsesOnItsSide) {
  for (const GoodRow& row : good_rows()) {
    auto parsed = parse_endpoint(row.text, row.use);
    ASSERT_TRUE(parsed) << row.text << ": " << describe(parsed.error());
    EXPECT_EQ(*parsed, row.expected) << row.text;
  }
}

TEST(Endpoint, ToString_RoundTrips) {
  for (const GoodRow& row : good_rows()) {
    const std::string text = to_string(row.expected);
    auto parsed = parse_endpoint(text, row.use);
    ASSERT_TRUE(parsed) << row.text << " -> " << text << ": " << describe(parsed.error());
    EXPECT_EQ(*parsed, row.expected) << text;
  }
  EXPECT_EQ(to_string(CanEndpoint{"vcan0"}), "can:vcan0");
  EXPECT_EQ(to_string(CanEndpoint{"vcan0", 0x6C0, 0x6C1, false, true}), "can:vcan0:6C0:6C1");
  EXPECT_EQ(to_string(TcpEndpoint{"127.0.0.1"}), "tcp:127.0.0.1:49152");
  EXPECT_EQ(to_string(TcpEndpoint{"::1", 5}), "tcp:[::1]:5");
  EXPECT_EQ(to_string(SerialEndpoint{"/tmp/s", 115200, true}), "serial:pty:/tmp/s");
  EXPECT_EQ(to_string(SerialEndpoint{"/dev/ttyS0", 9600, false}), "serial:/dev/ttyS0:9600");
  EXPECT_EQ(to_string(SerialEndpoint{"/dev/x:5", 115200, false}), "serial:/dev/x:5:115200");
  EXPECT_EQ(to_string(TcpEndpoint{"[x", 1}), "tcp:[[x]:1");
}

TEST(Endpoint, ExpectedKind_IsEnforced) {
  for (const EndpointSide side : {EndpointSide::offer, EndpointSide::connect}) {
    EXPECT_TRUE(parse_endpoint("tcp:h:1", {side, EndpointExpect::tcp}));
    EXPECT_TRUE(parse_endpoint("tcp:h:1", {side, EndpointExpect::scanner}));
    EXPECT_TRUE(parse_endpoint("can:vcan0", {side, EndpointExpect::can}));
    EXPECT_TRUE(parse_endpoint("lpt:pty:/x", {side, EndpointExpect::lpt}));
    EXPECT_EQ(parse_endpoint("tcp:h:1", {side, EndpointExpect::can}).error().kind, EndpointErrorKind::wrong_kind);
    EXPECT_EQ(parse_endpoint("lpt:pty:/x", {side, EndpointExpect::scanner}).error().kind, EndpointErrorKind::wrong_kind);
    EXPECT_EQ(parse_endpoint("serial:pty:/x", {side, EndpointExpect::lpt}).error().kind, EndpointErrorKind::wrong_kind);
  }
}

struct BadRow {
  std::string text;
  EndpointUse use;
  EndpointErrorKind kind;
  std::string message;  // describe_for_option("--x", error)
};

TEST(Endpoint, EveryError_HasItsMessage) {
  const EndpointUse offer_tcp{EndpointSide::offer, EndpointExpect::tcp};
  const EndpointUse offer_lpt{EndpointSide::offer, EndpointExpect::lpt};
  const EndpointUse connect_lpt{EndpointSide::connect, EndpointExpect::lpt};
  const EndpointUse connect_scanner{EndpointSide::connect, EndpointExpect::scanner};
  const std::vector<BadRow> rows = {
      {"", kConnect, EndpointErrorKind::empty, "--x: endpoint ``: empty: expected can:, tcp:, serial: or lpt:"},
      {"udp:1.2.3.4", kConnect, EndpointErrorKind::unknown_scheme,
       "--x: endpoint `udp:1.2.3.4`: unknown scheme: expected can:, tcp:, serial: or lpt:"},
      {"CAN:vcan0", connect_scanner, EndpointErrorKind::unknown_scheme,
       "--x: endpoint `CAN:vcan0`: unknown scheme: expected can:, tcp: or serial:"},
      {"can:", kConnect, EndpointErrorKind::missing_field, "--x: endpoint `can:`: missing field: no CAN interface name"},
      {"can:isotp:", kConnect, EndpointErrorKind::missing_field,
       "--x: endpoint `can:isotp:`: missing field: no CAN interface name"},
      {"can:vcan0:6C0", kConnect, EndpointErrorKind::missing_field,
       "--x: endpoint `can:vcan0:6C0`: missing field: a request id needs a response id"},
      {"can:vcan0:6C0:6C1:1", kConnect, EndpointErrorKind::surplus_field,
       "--x: endpoint `can:vcan0:6C0:6C1:1`: surplus field: expected can:IFACE[:REQ:RESP]"},
      {"can:vcan0:800:6C1", kConnect, EndpointErrorKind::out_of_range,
       "--x: endpoint `can:vcan0:800:6C1`: out of range: CAN request id `800` is above 0x7FF"},
      {"can:vcan0:6C0:6C0", kOffer, EndpointErrorKind::out_of_range,
       "--x: endpoint `can:vcan0:6C0:6C0`: out of range: request and response ids must differ"},
      {"can:vcan0:xyz:6C1", kConnect, EndpointErrorKind::bad_number,
       "--x: endpoint `can:vcan0:xyz:6C1`: bad number: CAN request id `xyz` is not hex"},
      {"can:a_very_long_interface_name", kConnect, EndpointErrorKind::bad_name,
       "--x: endpoint `can:a_very_long_interface_name`: bad name: CAN interface name longer than 15 characters"},
      {"can:isotp:vcan0", kOffer, EndpointErrorKind::wrong_side,
       "--x: endpoint `can:isotp:vcan0`: wrong side: can:isotp: is a host's kernel socket; ldoem-emud offers "
       "can:IFACE[:REQ:RESP]"},
      {"tcp:", kConnect, EndpointErrorKind::missing_field, "--x: endpoint `tcp:`: missing field: no host"},
      {"tcp:host:0", kConnect, EndpointErrorKind::out_of_range, "--x: endpoint `tcp:host:0`: out of range: port must be 1..65535"},
      {"tcp:host:65536", kOffer, EndpointErrorKind::out_of_range,
       "--x: endpoint `tcp:host:65536`: out of range: port must be 0..65535 (0: any free port)"},
      {"tcp:host:http", kConnect, EndpointErrorKind::bad_number,
       "--x: endpoint `tcp:host:http`: bad number: port `http` is not a number"},
      {"tcp:host:1:2", kConnect, EndpointErrorKind::surplus_field,
       "--x: endpoint `tcp:host:1:2`: surplus field: expected tcp:HOST[:PORT]"},
      {"tcp:[::1", kConnect, EndpointErrorKind::missing_field,
       "--x: endpoint `tcp:[::1`: missing field: `[` without `]` around the address"},
      {"tcp:[::1]x", kConnect, EndpointErrorKind::surplus_field,
       "--x: endpoint `tcp:[::1]x`: surplus field: text after `]` must be `:PORT`"},
      {"serial:", kConnect, EndpointErrorKind::missing_field, "--x: endpoint `serial:`: missing field: no device path"},
      {"serial:/dev/ttyUSB0:1234", kConnect, EndpointErrorKind::unsupported_baud,
       "--x: endpoint `serial:/dev/ttyUSB0:1234`: unsupported baud rate: baud `1234` is not one of 4800 9600 19200 "
       "38400 57600 115200"},
      {"serial:/dev/ttyUSB0", kOffer, EndpointErrorKind::wrong_side,
       "--x: endpoint `serial:/dev/ttyUSB0`: wrong side: the emulator offers serial:pty:PATH (a pty symlinked at "
       "PATH), not a device"},
      {"serial:pty:/tmp/s:9600", kOffer, EndpointErrorKind::wrong_side,
       "--x: endpoint `serial:pty:/tmp/s:9600`: wrong side: the line speed is the host's choice (spec 3.4); offer "
       "serial:pty:PATH"},
      {"lpt:pty:", kConnect, EndpointErrorKind::missing_field, "--x: endpoint `lpt:pty:`: missing field: no device path"},
      {"lpt:gpio:", kOffer, EndpointErrorKind::missing_field, "--x: endpoint `lpt:gpio:`: missing field: no gpio chip"},
      {"lpt:/dev/parport0", offer_lpt, EndpointErrorKind::wrong_side,
       "--x: endpoint `lpt:/dev/parport0`: wrong side: a parallel port is the host's; the emulator offers "
       "lpt:pty:PATH or lpt:gpio:CHIP"},
      {"tcp:h:1", connect_lpt, EndpointErrorKind::wrong_kind,
       "--x: endpoint `tcp:h:1`: wrong kind: expected lpt:pty:PATH, lpt:gpio:CHIP or lpt:/dev/parportN"},
      {"lpt:pty:/x", connect_scanner, EndpointErrorKind::wrong_kind,
       "--x: endpoint `lpt:pty:/x`: wrong kind: an lpt: endpoint carries no telegrams; expected can:, tcp: or serial:"},
      {"garbage/with/slash", offer_tcp, EndpointErrorKind::unknown_scheme,
       "--x: endpoint `garbage/with/slash`: unknown scheme: expected tcp:HOST[:PORT]"},
  };
  for (const BadRow& row : rows) {
    auto parsed = parse_endpoint(row.text, row.use);
    ASSERT_FALSE(parsed) << row.text << " parsed";
    EXPECT_EQ(parsed.error().kind, row.kind) << row.text << ": " << describe(parsed.error());
    EXPECT_EQ(parsed.error().text, row.text);
    EXPECT_EQ(describe_for_option("--x", parsed.error()), row.message);
  }
}

struct OldRow {
  std::string option;
  std::string text;
  EndpointUse use;
  std::string message;
};

TEST(Endpoint, OldSpellings_NameTheNewOne) {
  const auto offer = [](EndpointExpect e) { return EndpointUse{EndpointSide::offer, e}; };
  const auto connect = [](EndpointExpect e) { return EndpointUse{EndpointSide::connect, e}; };
  const std::vector<OldRow> rows = {
      {"--tcp", "127.0.0.1:49152", offer(EndpointExpect::tcp),
       "--tcp 127.0.0.1:49152 is the old spelling; write --tcp tcp:127.0.0.1:49152 (docs/endpoints.md)"},
      {"--tcp", "localhost", offer(EndpointExpect::tcp),
       "--tcp localhost is the old spelling; write --tcp tcp:localhost (docs/endpoints.md)"},
      {"tcp", "49153", offer(EndpointExpect::tcp),
       "tcp 49153 is the old spelling; write tcp tcp:127.0.0.1:49153 (docs/endpoints.md)"},
      {"--serial", "pty:/tmp/x", offer(EndpointExpect::serial),
       "--serial pty:/tmp/x is the old spelling; write --serial serial:pty:/tmp/x (docs/endpoints.md)"},
      {"--serial", "/dev/ttyUSB0", connect(EndpointExpect::serial),
       "--serial /dev/ttyUSB0 is the old spelling; write --serial serial:/dev/ttyUSB0 (docs/endpoints.md)"},
      {"--lpt", "pty:/tmp/x", offer(EndpointExpect::lpt),
       "--lpt pty:/tmp/x is the old spelling; write --lpt lpt:pty:/tmp/x (docs/endpoints.md)"},
      {"--lpt", "gpio:ldoem-lpt", offer(EndpointExpect::lpt),
       "--lpt gpio:ldoem-lpt is the old spelling; write --lpt lpt:gpio:ldoem-lpt (docs/endpoints.md)"},
      {"--lpt", "pty:/tmp/x", connect(EndpointExpect::lpt),
       "--lpt pty:/tmp/x is the old spelling; write --lpt lpt:pty:/tmp/x (docs/endpoints.md)"},
      {"--lpt", "/dev/parport0", connect(EndpointExpect::lpt),
       "--lpt /dev/parport0 is the old spelling; write --lpt lpt:/dev/parport0 (docs/endpoints.md)"},
      {"--can", "vcan0", offer(EndpointExpect::can),
       "--can vcan0 is the old spelling; write --can can:vcan0 (docs/endpoints.md)"},
      {"--device", "vcan0", connect(EndpointExpect::scanner),
       "--device vcan0 is the old spelling; write --device can:vcan0 (docs/endpoints.md)"},
      {"--device", "127.0.0.1:49152", connect(EndpointExpect::scanner),
       "--device 127.0.0.1:49152 is the old spelling; write --device tcp:127.0.0.1:49152 (docs/endpoints.md)"},
      {"--device", "pty:/tmp/s", connect(EndpointExpect::scanner),
       "--device pty:/tmp/s is the old spelling; write --device serial:pty:/tmp/s (docs/endpoints.md)"},
  };
  for (const OldRow& row : rows) {
    auto parsed = parse_endpoint(row.text, row.use);
    ASSERT_FALSE(parsed) << row.text << " parsed";
    ASSERT_EQ(parsed.error().kind, EndpointErrorKind::old_spelling) << row.text << ": " << describe(parsed.error());
    EXPECT_EQ(describe_for_option(row.option, parsed.error()), row.message);
    EXPECT_TRUE(parse_endpoint(parsed.error().suggestion, row.use)) << parsed.error().suggestion;
  }
  // An old spelling whose new text would not parse on that side is no suggestion.
  EXPECT_EQ(parse_endpoint("/dev/parport0", {EndpointSide::offer, EndpointExpect::lpt}).error().kind,
            EndpointErrorKind::unknown_scheme);
}

TEST(Endpoint, CanUnsupportedHint_SaysWhatToDo) {
  const std::string hint = can_unsupported_hint();
  EXPECT_NE(hint.find("modprobe vcan"), std::string::npos);
  EXPECT_NE(hint.find("docs/uml-harness.md"), std::string::npos);
  EXPECT_EQ(hint.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace ldoem::base
