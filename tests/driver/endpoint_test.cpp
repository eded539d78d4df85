#include "ldoem/driver/endpoint.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ldoem::driver {
namespace {

struct ParsedRow {
  std::string text;
  Endpoint expected;
};

std::vector<ParsedRow> good_rows() {
  return {
      {"can:vcan0", CanEndpoint{"vcan0", 0x6C0, 0x6C1, false}},
      {"can:vcan0:6C0:6C1", CanEndpoint{"vcan0", 0x6C0, 0x6C1, false, true}},
      {"can:can1:123:7ff", CanEndpoint{"can1", 0x123, 0x7FF, false, true}},
      {"can:vcan0:0x6C2:0x6C3", CanEndpoint{"vcan0", 0x6C2, 0x6C3, false, true}},
      {"can:isotp:vcan0", CanEndpoint{"vcan0", 0x6C0, 0x6C1, true}},
      {"can:isotp:vcan0:100:101", CanEndpoint{"vcan0", 0x100, 0x101, true, true}},
      {"tcp:127.0.0.1:49152", TcpEndpoint{"127.0.0.1", 49152}},
      {"tcp:127.0.0.1", TcpEndpoint{"127.0.0.1", 49152}},
      {"tcp:scanner.lab:5000", TcpEndpoint{"scanner.lab", 5000}},
      {"tcp:[::1]:49153", TcpEndpoint{"::1", 49153}},
      {"tcp:[::1]", TcpEndpoint{"::1", 49152}},
      {"serial:/dev/ttyUSB0", SerialEndpoint{"/dev/ttyUSB0", 115200}},
      {"serial:/dev/ttyUSB0:115200", SerialEndpoint{"/dev/ttyUSB0", 115200}},
      {"serial:/dev/ttyS1:9600", SerialEndpoint{"/dev/ttyS1", 9600}},
      {"serial:pty:/tmp/ldoem-serial", SerialEndpoint{"/tmp/ldoem-serial", 115200, true}},
      {"serial:pty:/tmp/ldoem-serial:57600", SerialEndpoint{"/tmp/ldoem-serial", 57600, true}},
      {"lpt:/dev/parport0", LptEndpoint{LptBackend::ppdev, "/dev/parport0"}},
      {"lpt:pty:/tmp/ldoem-lpt", LptEndpoint{LptBackend::pty, "/tmp/ldoem-lpt"}},
      {"lpt:gpio:ldoem-lpt", LptEndpoint{LptBackend::gpio, "ldoem-lpt"}},
  };
}

TEST(ParseEndpoint, ValidStrings_GiveTypedEndpoints) {
  for (const ParsedRow& row : good_rows()) {
    auto parsed = parse_endpoint(row.text);
    ASSERT_TRUE(parsed) << row.text << ": " << describe(parsed.error());
    EXPECT_EQ(*parsed, row.expected) << row.text;
  }
}

TEST(ParseEndpoint, FormattedEndpoint_ParsesBackToItself) {
  for (const ParsedRow& row : good_rows()) {
    const std::string text = format_endpoint(row.expected);
    auto parsed = parse_endpoint(text);
    ASSERT_TRUE(parsed) << text;
    EXPECT_EQ(*parsed, row.expected) << text;
  }
}

TEST(ParseEndpoint, DefaultCanIds_AreD1Values) {
  EXPECT_EQ(kDefaultCanRequestId, 0x6C0u);
  EXPECT_EQ(kDefaultCanResponseId, 0x6C1u);
  EXPECT_EQ(base::kHostTcpPort, 49152);
  EXPECT_EQ(format_endpoint(CanEndpoint{"vcan0"}), "can:vcan0");
}

struct RefusedRow {
  std::string text;
  EndpointErrorKind kind;
};

TEST(ParseEndpoint, InvalidStrings_GiveTypedErrors) {
  const std::vector<RefusedRow> rows = {
      {"", EndpointErrorKind::empty},
      {"udp:1.2.3.4", EndpointErrorKind::unknown_scheme},
      {"vcan0", EndpointErrorKind::old_spelling},  // write can:vcan0 (docs/endpoints.md)
      {"CAN:vcan0", EndpointErrorKind::unknown_scheme},
      {"can:", EndpointErrorKind::missing_field},
      {"can:isotp:", EndpointErrorKind::missing_field},
      {"can:vcan0:6C0", EndpointErrorKind::missing_field},
      {"can:vcan0:6C0:6C1:1", EndpointErrorKind::surplus_field},
      {"can:vcan0:800:6C1", EndpointErrorKind::out_of_range},
      {"can:vcan0:6C0:6C0", EndpointErrorKind::out_of_range},
      {"can:vcan0:xyz:6C1", EndpointErrorKind::bad_number},
      {"can:vcan0:6C0:", EndpointErrorKind::bad_number},
      {"can:a_very_long_interface_name", EndpointErrorKind::bad_name},
      {"tcp:", EndpointErrorKind::missing_field},
      {"tcp::49152", EndpointErrorKind::missing_field},
      {"tcp:host:0", EndpointErrorKind::out_of_range},
      {"tcp:host:65536", EndpointErrorKind::out_of_range},
      {"tcp:host:http", EndpointErrorKind::bad_number},
      {"tcp:host:1:2", EndpointErrorKind::surplus_field},
      {"tcp:[::1", EndpointErrorKind::missing_field},
      {"tcp:[::1]x", EndpointErrorKind::surplus_field},
      {"serial:", EndpointErrorKind::missing_field},
      {"serial:/dev/ttyUSB0:1234", EndpointErrorKind::unsupported_baud},
      {"serial::9600", EndpointErrorKind::missing_field},
      {"lpt:", EndpointErrorKind::missing_field},
      {"lpt:pty:", EndpointErrorKind::missing_field},
      {"lpt:gpio:", EndpointErrorKind::missing_field},
  };
  for (const RefusedRow& row : rows) {
    auto parsed = parse_endpoint(row.text);
    ASSERT_FALSE(parsed) << row.text << " parsed";
    EXPECT_EQ(parsed.error().kind, row.kind) << row.text << ": " << describe(parsed.error());
    EXPECT_EQ(parsed.error().text, row.text);
  }
}

TEST(DescribeEndpointError, NamesTheStringAndTheField) {
  auto parsed = parse_endpoint("can:vcan0:800:6C1");
  ASSERT_FALSE(parsed);
  EXPECT_EQ(describe(parsed.error()), "endpoint `can:vcan0:800:6C1`: out of range: CAN request id `800` is above 0x7FF");
}

}  // namespace
}  // namespace ldoem::driver
