// TcpTransport against an in-test server on 127.0.0.1: the exact frames of spec 7.1 go out,
// the frames of 7.2 come back, in S1's conversation of spec 7.3.
#include "ldoem/driver/tcp_transport.hpp"

#include <gtest/gtest.h>

#include "ldoem/driver/scanner.hpp"
#include "tcp_server.hpp"
#include "test_support.hpp"

namespace ldoem::driver {
namespace {

using test::hex_text;
using test::ScriptedTcpServer;
using test::ServerStep;
using test::SpecVectors;
using test::tcp_payload;
using namespace std::chrono_literals;

const SpecVectors& vectors() { return SpecVectors::get(); }

std::unique_ptr<TcpTransport> connect_to(std::uint16_t port) {
  auto transport = TcpTransport::connect(TcpEndpoint{"127.0.0.1", port});
  if (!transport) {
    ADD_FAILURE() << describe(transport.error());
    return nullptr;
  }
  return std::move(*transport);
}

TEST(TcpTransport, EverySpecRequest_GoesOutAsTheExactFrame) {
  Bytes expected;
  for (const auto& [name, frame] : vectors().tcp_requests) {
    expected.insert(expected.end(), frame.begin(), frame.end());
  }
  ScriptedTcpServer server({ServerStep{expected.size(), {}}});
  auto transport = connect_to(server.port());
  ASSERT_TRUE(transport);
  for (const auto& [name, frame] : vectors().tcp_requests) {
    ASSERT_TRUE(transport->send(tcp_payload(frame), Clock::now() + 5s)) << name;
  }
  transport->close();
  EXPECT_EQ(hex_text(server.received()), hex_text(expected));
  EXPECT_EQ(transport->counters().telegrams_sent, vectors().tcp_requests.size());
}

TEST(TcpTransport, SpecReplies_ArriveAsPayloads) {
  Bytes all_replies;
  for (const auto& [name, frame] : vectors().tcp_replies) {
    all_replies.insert(all_replies.end(), frame.begin(), frame.end());
  }
  ScriptedTcpServer server({ServerStep{0, all_replies}});
  auto transport = connect_to(server.port());
  ASSERT_TRUE(transport);
  for (const auto& [name, frame] : vectors().tcp_replies) {
    auto payload = transport->receive(Clock::now() + 5s);
    ASSERT_TRUE(payload) << name << ": " << describe(payload.error());
    EXPECT_EQ(hex_text(*payload), hex_text(tcp_payload(frame))) << name;
  }
}

TEST(TcpTransport, BadChecksumFrame_IsDroppedSilentlyAndCounted) {
  Bytes corrupted = vectors().reply("GET_STATUS, IDLE, motor OK");
  corrupted.back() ^= 0xFF;
  Bytes stream = corrupted;
  const Bytes& good = vectors().reply("GET_SIGNAL port 0x01");
  stream.insert(stream.end(), good.begin(), good.end());
  ScriptedTcpServer server({ServerStep{0, stream}});
  auto transport = connect_to(server.port());
  ASSERT_TRUE(transport);
  auto payload = transport->receive(Clock::now() + 5s);
  ASSERT_TRUE(payload);
  EXPECT_EQ(*payload, tcp_payload(good));
  EXPECT_EQ(transport->counters().dropped_frames, 1u);
}

TEST(TcpTransport, PeerClose_IsConnectionClosed_RetryableAfterAReconnect) {
  ScriptedTcpServer server({}, /*close_after=*/true);
  auto transport = connect_to(server.port());
  ASSERT_TRUE(transport);
  auto payload = transport->receive(Clock::now() + 5s);
  ASSERT_FALSE(payload);
  EXPECT_EQ(payload.error().kind, ErrorKind::connection_closed);
  EXPECT_EQ(recovery_for(payload.error()), Recovery::reconnect);
}

TEST(TcpTransport, NothingArrives_IsRetryableTimeout) {
  ScriptedTcpServer server({ServerStep{2 + 9, {}}});  // waits for the client's frame, never answers
  auto transport = connect_to(server.port());
  ASSERT_TRUE(transport);
  auto payload = transport->receive(Clock::now() + 20ms);
  ASSERT_FALSE(payload);
  EXPECT_EQ(payload.error().kind, ErrorKind::timeout);
  EXPECT_TRUE(is_retryable(payload.error()));
  ASSERT_TRUE(transport->send(Bytes{0x01, 0x02}, Clock::now() + 1s));  // lets the server finish
}

TEST(TcpTransport, ConnectToClosedPort_IsFinalErrorNamingTheEndpoint) {
  std::uint16_t closed_port = 0;
  {
    ScriptedTcpServer server({}, /*close_after=*/true);
    closed_port = server.port();
    auto transport = connect_to(server.port());  // let the server's accept finish
  }
  auto transport = TcpTransport::connect(TcpEndpoint{"127.0.0.1", closed_port});
  ASSERT_FALSE(transport);
  EXPECT_FALSE(is_retryable(transport.error()));
  EXPECT_EQ(transport.error().operation, "connect");
  EXPECT_EQ(transport.error().object, "tcp:127.0.0.1:" + std::to_string(closed_port));
}

TEST(TcpTransport, ClosedTransport_RefusesToSend) {
  ScriptedTcpServer server({}, /*close_after=*/true);
  auto transport = connect_to(server.port());
  ASSERT_TRUE(transport);
  transport->close();
  auto sent = transport->send(Bytes{0x01, 0x02}, Clock::now() + 1s);
  ASSERT_FALSE(sent);
  EXPECT_EQ(sent.error().kind, ErrorKind::connection_closed);
}

// Spec 7.3: S1's conversation, driven through the Scanner, frame for frame.
TEST(TcpTransport, S1Conversation_SendsSpecFramesAndParsesReplies) {
  std::vector<ServerStep> steps;
  std::vector<std::string> request_names;
  auto step = [&](const std::string& request, const Bytes& reply) {
    request_names.push_back(request);
    steps.push_back(ServerStep{vectors().request(request).size(), reply});
  };
  const Bytes ident = vectors().reply("GET_IDENTIFICATION, text 'LD-OEM' (text illustrative)");
  step("GET_STATUS", vectors().reply("GET_STATUS, IDLE, motor OK"));
  for (const char* item : {"0x00", "0x01", "0x02", "0x03", "0x04", "0x10", "0x11", "0x12", "0x20", "0x21", "0x22"}) {
    step(std::string("GET_IDENTIFICATION ") + item, ident);
  }
  step("GET_CONFIG Ethernet", vectors().reply("GET_CONFIG Ethernet 192.168.1.10/255.255.255.0/192.168.1.1, node 0, port 0"));
  step("GET_CONFIG global", vectors().reply("GET_CONFIG global (1, 10 Hz, 8 ticks)"));
  step("GET_FUNCTION s0", vectors().reply("GET_FUNCTION s0 normal 270°"));
  step("SET_SIGNAL 0x00", vectors().reply("SET_SIGNAL accepted"));
  step("TRANS_ROTATE (flash speed)", vectors().reply("TRANS_ROTATE → ROTATE, motor OK"));
  step("TRANS_MEASURE", vectors().reply("TRANS_MEASURE OK"));
  step("GET_PROFILE stream 0x39FF",
       vectors().reply("Profile 0x39FF: sent 1, count 100, layer 0, sector 0, step 0.5°, 3 points, t 0x1234→0x1236 "
                       "ms, 0°→1°, distances 1 m / 2.5 m / 0"));
  step("CANCEL_PROFILE", vectors().reply("CANCEL_PROFILE, MEASURE"));
  step("TRANS_ROTATE (flash speed)", vectors().reply("TRANS_ROTATE → ROTATE, motor OK"));
  step("TRANS_IDLE", vectors().reply("TRANS_IDLE → IDLE"));
  step("SET_SIGNAL 0x00", vectors().reply("SET_SIGNAL accepted"));

  ScriptedTcpServer server(steps);
  auto transport = connect_to(server.port());
  ASSERT_TRUE(transport);
  Scanner scanner(std::move(transport));
  ASSERT_TRUE(scanner.connect());
  auto ids = scanner.identify_all();
  ASSERT_TRUE(ids);
  EXPECT_EQ(ids->front().text, "LD-OEM");
  ASSERT_TRUE(scanner.get_ethernet_config());
  auto global = scanner.get_global_config();
  ASSERT_TRUE(global);
  EXPECT_EQ(global->motor_speed_hz, 10);
  auto sector = scanner.get_function(0);
  ASSERT_TRUE(sector);
  EXPECT_EQ(sector->function, 3);  // normal measurement: S1 stops reading here
  ASSERT_TRUE(scanner.set_signal(0));
  ASSERT_TRUE(scanner.trans_rotate());
  ASSERT_TRUE(scanner.trans_measure());
  ASSERT_TRUE(scanner.get_profile(0, protocol::kFormatRange));
  auto profile = scanner.next_profile(Clock::now() + 5s);
  ASSERT_TRUE(profile) << describe(profile.error());
  EXPECT_EQ(profile->sectors.at(0).points.size(), 3u);
  ASSERT_TRUE(scanner.cancel_profile());
  ASSERT_TRUE(scanner.trans_rotate());
  ASSERT_TRUE(scanner.trans_idle());
  ASSERT_TRUE(scanner.set_signal(0));
  scanner.close();

  Bytes expected;
  for (const std::string& name : request_names) {
    const Bytes& frame = vectors().request(name);
    expected.insert(expected.end(), frame.begin(), frame.end());
  }
  EXPECT_EQ(hex_text(server.received()), hex_text(expected));
}

TEST(OpenTransport, LptEndpoint_IsInvalidArgument) {
  auto transport = open_transport(LptEndpoint{LptBackend::pty, "/tmp/x"});
  ASSERT_FALSE(transport);
  EXPECT_EQ(transport.error().kind, ErrorKind::invalid_argument);
}

}  // namespace
}  // namespace ldoem::driver
