// D11 wire faults on the stream transports (TCP spec 4.1, serial spec 4.2), produced inside the
// endpoints: corrupt_checksum and garbage on both, tcp_stall and bandwidth on TCP. Each test
// asserts the bytes on the wire or the time they arrive, and, where it is simple, what libldoem
// makes of them.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>

#include "ldoem/driver/transport.hpp"
#include "ldoem/faults/fault_scheduler.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/protocol/wire_corruption.hpp"
#include "wire_fault_support.hpp"

namespace ldoem::wire_faults::test {
namespace {

using namespace std::chrono_literals;
using daemon::test::hex;
using daemon::test::minimal_scene_text;
using daemon::test::TcpHost;
using daemon::test::telegram;
using daemon::test::to_hex;
using base::SimTime;

// spec 7.3: GET_STATUS and its reply in IDLE, framed for TCP.
const std::string kGoodStatusFrame = "02 55 53 50 00 00 00 06 81 02 00 00 00 01 82";
// The same frame with the XOR byte inverted (0x82 ^ 0xFF).
const std::string kCorruptStatusFrame = "02 55 53 50 00 00 00 06 81 02 00 00 00 01 7D";
// spec 7.4: the serial GET_STATUS request, and our one-package reply: its CRC is 0xab0e, the
// corrupted one 0xab0e ^ 0xFFFF = 0x54f1 (computed apart from the code, from spec 4.2's register form).
const std::string kSerialGetStatus = "\x02" "00100003000001026d36" "\x03";
const std::string kSerialStatusReply = "\x02" "1000000600000001810200000001" "ab0e" "\x03";
const std::string kSerialCorruptReply = "\x02" "1000000600000001810200000001" "54f1" "\x03";

std::string scene_with(const std::string& faults) { return minimal_scene_text() + "seed: 7\nfaults:\n" + faults; }

Bytes as_bytes(const std::string& text) { return Bytes(text.begin(), text.end()); }

driver::Deadline in(std::chrono::milliseconds limit) { return driver::Clock::now() + limit; }

std::unique_ptr<driver::TelegramTransport> open(const std::string& endpoint_text) {
  auto endpoint = driver::parse_endpoint(endpoint_text);
  EXPECT_TRUE(endpoint) << endpoint_text;
  if (!endpoint) return nullptr;
  auto transport = driver::open_transport(*endpoint);
  EXPECT_TRUE(transport) << (transport ? "" : driver::describe(transport.error()));
  return transport ? std::move(*transport) : nullptr;
}

// ------------------------------------------------------------------------------ corrupt_checksum

TEST(WireFaultsTcp, CorruptChecksum_InvertsTheXorByteOfTheNamedReply) {
  FaultyDaemon d(scene_with("  - kind: corrupt_checksum\n    on: {service: GET_STATUS, nth: 2}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto host = TcpHost::connect(d.process->tcp_port());
  ASSERT_TRUE(host);
  for (const std::string& expected : {kGoodStatusFrame, kCorruptStatusFrame, kGoodStatusFrame}) {
    host->send(telegram("GET_STATUS"));
    EXPECT_EQ(to_hex(read_bytes(host->fd(), 15)), expected);
  }
  Bytes computed = hex(kGoodStatusFrame);
  ASSERT_TRUE(protocol::corrupt_tcp_checksum(computed));
  EXPECT_EQ(to_hex(computed), kCorruptStatusFrame);
  EXPECT_NE(d.events().find("\"kind\":\"corrupt_checksum\""), std::string::npos) << d.events();
}

TEST(WireFaultsTcp, CorruptChecksum_LibldoemDropsTheFrameCountsItAndTimesOutRetryably) {
  FaultyDaemon d(scene_with("  - kind: corrupt_checksum\n    on: {service: GET_STATUS, nth: 1}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto transport = open("tcp:127.0.0.1:" + std::to_string(d.process->tcp_port()));
  ASSERT_TRUE(transport);
  ASSERT_TRUE(transport->send(telegram("GET_STATUS"), in(2s)));
  const auto lost = transport->receive(in(500ms));
  ASSERT_FALSE(lost);
  EXPECT_EQ(lost.error().kind, driver::ErrorKind::timeout);
  EXPECT_TRUE(driver::is_retryable(lost.error()));
  EXPECT_EQ(transport->counters().dropped_frames, 1u);
  ASSERT_TRUE(transport->send(telegram("GET_STATUS"), in(2s)));  // the retry gets its reply
  const auto again = transport->receive(in(5s));
  ASSERT_TRUE(again);
  EXPECT_EQ(protocol::format_telegram(*again), "GET_STATUS reply 0000 0001");
}

TEST(WireFaultsSerial, CorruptChecksum_InvertsTheCrcOfTheReply) {
  TempDir pty_dir;
  FaultyDaemon d(scene_with("  - kind: corrupt_checksum\n    on: {service: GET_STATUS, nth: 2}\n"),
                 {"--serial", "serial:pty:" + pty_dir.path("serial")});
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  const int fd = open_raw(pty_dir.path("serial"));
  ASSERT_GE(fd, 0);
  for (const std::string& expected : {kSerialStatusReply, kSerialCorruptReply, kSerialStatusReply}) {
    ASSERT_EQ(::write(fd, kSerialGetStatus.data(), kSerialGetStatus.size()), static_cast<ssize_t>(kSerialGetStatus.size()));
    EXPECT_EQ(to_hex(read_bytes(fd, expected.size())), to_hex(as_bytes(expected)));
  }
  ::close(fd);
}

TEST(WireFaultsSerial, CorruptChecksum_LibldoemDropsThePackageAndTimesOut) {
  TempDir pty_dir;
  FaultyDaemon d(scene_with("  - kind: corrupt_checksum\n    on: {service: GET_STATUS, nth: 1}\n"),
                 {"--serial", "serial:pty:" + pty_dir.path("serial")});
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto transport = open("serial:pty:" + pty_dir.path("serial"));
  ASSERT_TRUE(transport);
  ASSERT_TRUE(transport->send(telegram("GET_STATUS"), in(2s)));
  const auto lost = transport->receive(in(500ms));
  ASSERT_FALSE(lost);
  EXPECT_EQ(lost.error().kind, driver::ErrorKind::timeout);
  EXPECT_EQ(transport->counters().dropped_frames, 1u);
  ASSERT_TRUE(transport->send(telegram("GET_STATUS"), in(2s)));
  const auto again = transport->receive(in(5s));
  ASSERT_TRUE(again);
  EXPECT_EQ(protocol::format_telegram(*again), "GET_STATUS reply 0000 0001");
}

// ------------------------------------------------------------------------------------ garbage

// Fault 1 of a scene with seed 7: the bytes are fault_garbage(7, 1, n), and none is 0x02.
TEST(WireFaultsTcp, Garbage_PutsTheSeededBytesBeforeTheFrame) {
  FaultyDaemon d(scene_with("  - kind: garbage\n    bytes: 12\n    on: {service: GET_STATUS, nth: 1}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto host = TcpHost::connect(d.process->tcp_port());
  ASSERT_TRUE(host);
  host->send(telegram("GET_STATUS"));
  const std::vector<std::uint8_t> garbage = faults::fault_garbage(7, 1, 12);
  ASSERT_EQ(garbage.size(), 12u);
  for (const std::uint8_t byte : garbage) EXPECT_NE(byte, 0x02);
  EXPECT_EQ(to_hex(read_bytes(host->fd(), 12 + 15)), to_hex(garbage) + " " + kGoodStatusFrame);
  host->send(telegram("GET_STATUS"));  // one telegram only
  EXPECT_EQ(to_hex(read_bytes(host->fd(), 15)), kGoodStatusFrame);
}

TEST(WireFaultsTcp, Garbage_LibldoemSkipsItAndReadsTheTelegram) {
  FaultyDaemon d(scene_with("  - kind: garbage\n    bytes: 40\n    on: {service: GET_STATUS, nth: 1}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto transport = open("tcp:127.0.0.1:" + std::to_string(d.process->tcp_port()));
  ASSERT_TRUE(transport);
  ASSERT_TRUE(transport->send(telegram("GET_STATUS"), in(2s)));
  const auto reply = transport->receive(in(5s));
  ASSERT_TRUE(reply);
  EXPECT_EQ(protocol::format_telegram(*reply), "GET_STATUS reply 0000 0001");
  EXPECT_EQ(transport->counters().skipped_bytes, 40u);
  EXPECT_EQ(transport->counters().dropped_frames, 0u);
}

TEST(WireFaultsSerial, Garbage_PutsTheSeededBytesBeforeTheReply_LibldoemSkipsThem) {
  TempDir pty_dir;
  FaultyDaemon d(scene_with("  - kind: garbage\n    bytes: 9\n    every: {service: GET_STATUS, count: 1}\n"),
                 {"--serial", "serial:pty:" + pty_dir.path("serial")});
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  {
    const int fd = open_raw(pty_dir.path("serial"));
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::write(fd, kSerialGetStatus.data(), kSerialGetStatus.size()), static_cast<ssize_t>(kSerialGetStatus.size()));
    const Bytes expected_reply = as_bytes(kSerialStatusReply);
    EXPECT_EQ(to_hex(read_bytes(fd, 9 + expected_reply.size())),
              to_hex(faults::fault_garbage(7, 1, 9)) + " " + to_hex(expected_reply));
    ::close(fd);
  }
  auto transport = open("serial:pty:" + pty_dir.path("serial"));
  ASSERT_TRUE(transport);
  ASSERT_TRUE(transport->send(telegram("GET_STATUS"), in(2s)));
  const auto reply = transport->receive(in(5s));
  ASSERT_TRUE(reply);
  EXPECT_EQ(protocol::format_telegram(*reply), "GET_STATUS reply 0000 0001");
  EXPECT_EQ(transport->counters().skipped_bytes, 9u);
}

// ---------------------------------------------------------------------------- tcp_stall, bandwidth

TEST(WireFaultsTcp, TcpStall_NeitherReadsNorWritesForItsDuration) {
  InProcessTcp d(scene_with("  - kind: tcp_stall\n    duration_s: 2\n    on: {service: GET_STATUS, nth: 1}\n"));
  ASSERT_TRUE(d.daemon) << d.failure;
  auto host = TcpHost::connect(*d.daemon->tcp_port());
  ASSERT_TRUE(host);
  const SimTime asked = d.daemon->now();
  host->send(telegram("GET_STATUS"));
  // The request is read (it triggers the stall); then the connection stops.
  ASSERT_TRUE(d.run_until([&] { return d.daemon->counters().telegrams_received == 1; }));
  host->send(telegram("GET_SIGNAL"));  // sent during the stall: not read before it ends
  const auto first = d.receive(host->fd(), 15);
  EXPECT_EQ(to_hex(first.bytes), kGoodStatusFrame);
  EXPECT_GE(first.at - asked, SimTime(2s));
  EXPECT_LT(first.at - asked, SimTime(2100ms));
  const auto second = d.receive(host->fd(), 8 + 4 + 1);
  EXPECT_EQ(to_hex(second.bytes), "02 55 53 50 00 00 00 04 81 04 00 00 85");  // GET_SIGNAL reply 0000
  EXPECT_EQ(d.daemon->counters().telegrams_received, 2u);
  EXPECT_GE(second.at, first.at);
}

TEST(WireFaultsTcp, Bandwidth_TenBytesPerSecondDeliverAFifteenByteFrameInOnePointFiveSeconds) {
  InProcessTcp d(scene_with("  - kind: bandwidth\n    bytes_per_s: 10\n"));
  ASSERT_TRUE(d.daemon) << d.failure;
  auto host = TcpHost::connect(*d.daemon->tcp_port());
  ASSERT_TRUE(host);
  const SimTime asked = d.daemon->now();
  host->send(telegram("GET_STATUS"));
  const auto first_byte = d.receive(host->fd(), 1);
  EXPECT_EQ(to_hex(first_byte.bytes), "02");
  EXPECT_EQ(first_byte.at - asked, SimTime(100ms));  // one byte per 1/10 s
  const auto rest = d.receive(host->fd(), 14);
  EXPECT_EQ("02 " + to_hex(rest.bytes), kGoodStatusFrame);  // the bytes are untouched
  EXPECT_EQ(rest.at - asked, SimTime(1500ms));
}

// ----------------------------------------------------------------------------------- determinism

// Same scene, seed and conversation: the same bytes on the wire and the same event log, twice,
// with probability-triggered endpoint faults (D11: counter-based draws from the seed).
TEST(WireFaultsTcp, SameSeedAndConversationGiveTheSameBytesAndEventsTwice) {
  const std::string scene = minimal_scene_text() + "seed: 99\nfaults:\n"
                            "  - {kind: garbage, bytes: 5, probability: 0.3, service: GET_STATUS}\n"
                            "  - {kind: corrupt_checksum, probability: 0.25, service: GET_STATUS}\n"
                            "  - {kind: corrupt_checksum, every: {service: GET_CONFIG, count: 2}}\n";
  auto run = [&scene] {
    FaultyDaemon d(scene);
    EXPECT_TRUE(d.ready()) << d.diagnostics();
    std::string transcript;
    auto host = TcpHost::connect(d.process->tcp_port());
    if (!host) return std::pair<std::string, std::string>{};
    auto ask = [&](std::string_view request) {
      host->send(telegram(request));
      // Every reply is one frame, maybe after garbage: read until the frame's last byte.
      Bytes bytes = read_bytes(host->fd(), 15, 2s);
      while (!bytes.empty() && bytes.size() < 64) {
        const auto header = std::search(bytes.begin(), bytes.end(), protocol::kTcpMagic.begin(), protocol::kTcpMagic.end());
        const auto offset = static_cast<std::size_t>(header - bytes.begin());
        if (header != bytes.end() && bytes.size() >= offset + protocol::kTcpHeaderSize &&
            bytes.size() >= offset + protocol::tcp_frame_size(protocol::read_u32_be(bytes, offset + 4))) {
          break;
        }
        const Bytes more = read_bytes(host->fd(), 1, 2s);
        if (more.empty()) break;
        bytes.insert(bytes.end(), more.begin(), more.end());
      }
      transcript += std::string(request) + " -> " + to_hex(bytes) + "\n";
    };
    for (int i = 0; i < 16; ++i) ask("GET_STATUS");
    for (int i = 0; i < 4; ++i) ask("GET_CONFIG 0010");
    d.process->signal(SIGTERM);
    d.process->wait();
    return std::pair{transcript, d.events()};
  };
  const auto first = run_twice_expect_same(run);
  EXPECT_NE(first.first.find("GET_STATUS -> " + kCorruptStatusFrame), std::string::npos) << first.first;
  EXPECT_NE(first.first.find("GET_STATUS -> " + kGoodStatusFrame), std::string::npos) << first.first;
  std::size_t garbled = 0;  // replies with bytes before their header
  for (std::size_t at = first.first.find("GET_STATUS -> "); at != std::string::npos; at = first.first.find("GET_STATUS -> ", at + 1)) {
    if (first.first.compare(at + 14, 11, "02 55 53 50") != 0) ++garbled;
  }
  EXPECT_GT(garbled, 0u) << first.first;
  EXPECT_LT(garbled, 16u) << first.first;
  EXPECT_NE(first.second.find("\"kind\":\"garbage\""), std::string::npos) << first.second;
}

// The same on serial: probability-triggered and counted faults in the endpoint (garbage,
// corrupt_checksum) and in the wire tap (drop_reply), the bytes read off the pty and the event
// log, twice.
TEST(WireFaultsSerial, SameSeedAndConversationGiveTheSameBytesAndEventsTwice) {
  const std::string scene = minimal_scene_text() + "seed: 41\nfaults:\n"
                            "  - {kind: garbage, bytes: 6, probability: 0.3, service: GET_STATUS}\n"
                            "  - {kind: corrupt_checksum, count: 2, every: {service: GET_CONFIG, count: 3}}\n"
                            "  - {kind: drop_reply, probability: 0.2, service: GET_STATUS}\n";
  auto run = [&scene] {
    TempDir pty_dir;
    FaultyDaemon d(scene, {"--serial", "serial:pty:" + pty_dir.path("serial")});
    EXPECT_TRUE(d.ready()) << d.diagnostics();
    std::string transcript;
    const int fd = open_raw(pty_dir.path("serial"));
    if (fd < 0) return std::pair<std::string, std::string>{};
    auto ask = [&](std::string_view request) {
      const Bytes package = protocol::encode_serial_request(telegram(request));
      EXPECT_EQ(::write(fd, package.data(), package.size()), static_cast<ssize_t>(package.size()));
      // A reply is garbage (never STX) then STX .. ETX; a dropped one is nothing.
      Bytes bytes;
      for (Bytes more = read_bytes(fd, 1, 300ms); !more.empty(); more = read_bytes(fd, 1, 300ms)) {
        bytes.insert(bytes.end(), more.begin(), more.end());
        const auto stx = std::find(bytes.begin(), bytes.end(), std::uint8_t{0x02});
        if (stx != bytes.end() && std::find(stx, bytes.end(), std::uint8_t{0x03}) != bytes.end()) break;
        if (bytes.size() > 256) break;
      }
      transcript += std::string(request) + " -> " + (bytes.empty() ? std::string("(nothing)") : to_hex(bytes)) + "\n";
    };
    for (int i = 0; i < 16; ++i) ask("GET_STATUS");
    for (int i = 0; i < 6; ++i) ask("GET_CONFIG 0010");
    ::close(fd);
    d.process->signal(SIGTERM);
    d.process->wait();
    return std::pair{transcript, d.events()};
  };
  const auto first = run_twice_expect_same(run);
  const std::string good = "GET_STATUS -> " + to_hex(as_bytes(kSerialStatusReply)) + "\n";
  EXPECT_NE(first.first.find(good), std::string::npos) << first.first;
  EXPECT_NE(first.first.find("GET_STATUS -> (nothing)"), std::string::npos) << first.first;  // dropped
  std::size_t garbled = 0;  // GET_STATUS replies with bytes before their STX
  for (std::size_t at = first.first.find("GET_STATUS -> "); at != std::string::npos; at = first.first.find("GET_STATUS -> ", at + 1)) {
    if (first.first.compare(at + 14, 2, "02") != 0 && first.first.compare(at + 14, 9, "(nothing)") != 0) ++garbled;
  }
  EXPECT_GT(garbled, 0u) << first.first;
  EXPECT_LT(garbled, 16u) << first.first;
  // every: GET_CONFIG 3 and 6 start a corrupt_checksum with count 2: replies 3, 4 and 6 are corrupted.
  std::vector<std::string> config_replies;
  for (std::size_t at = first.first.find("GET_CONFIG 0010 -> "); at != std::string::npos;
       at = first.first.find("GET_CONFIG 0010 -> ", at + 1)) {
    config_replies.push_back(first.first.substr(at, first.first.find('\n', at) - at));
  }
  ASSERT_EQ(config_replies.size(), 6u) << first.first;
  for (const std::size_t healthy : {1u, 4u}) EXPECT_EQ(config_replies[healthy], config_replies[0]);
  for (const std::size_t corrupted : {2u, 3u, 5u}) {
    EXPECT_NE(config_replies[corrupted], config_replies[0]);
    EXPECT_EQ(config_replies[corrupted].size(), config_replies[0].size());  // only the CRC differs
  }
  EXPECT_NE(first.second.find("\"reason\":\"count used\""), std::string::npos) << first.second;
  EXPECT_NE(first.second.find("\"kind\":\"drop_reply\""), std::string::npos) << first.second;
}

// D9's rule for the endpoint hook: a scene whose faults never act gives the bytes of a scene
// without faults: a conversation with profiles, byte for byte, at the same simulated times.
TEST(WireFaultsTcp, AHookWithNoActiveFaultChangesNoByte) {
  auto conversation = [](const std::string& scene_text) {
    InProcessTcp d(scene_text);
    EXPECT_TRUE(d.daemon) << d.failure;
    std::string transcript;
    if (!d.daemon) return transcript;
    auto host = TcpHost::connect(*d.daemon->tcp_port());
    if (!host) return transcript;
    auto frame = [&] {
      const auto header = d.receive(host->fd(), protocol::kTcpHeaderSize);
      if (header.bytes.size() < protocol::kTcpHeaderSize) return std::string("(nothing)");
      const auto rest = d.receive(host->fd(), protocol::read_u32_be(header.bytes, 4) + protocol::kTcpTrailerSize);
      return std::to_string(rest.at.count()) + " " + to_hex(header.bytes) + " " + to_hex(rest.bytes);
    };
    for (const std::string_view request : {"GET_STATUS", "TRANS_ROTATE 0000", "TRANS_MEASURE", "GET_PROFILE 0005 39ff"}) {
      host->send(telegram(request));
      transcript += frame() + "\n";
    }
    for (int profile = 1; profile < 5; ++profile) transcript += frame() + "\n";
    return transcript;
  };
  const std::string plain = conversation(minimal_scene_text());
  const std::string dormant = conversation(scene_with(
      "  - {kind: garbage, at_s: 100000}\n  - {kind: corrupt_checksum, on: {service: GET_CONFIG, nth: 1}}\n"
      "  - {kind: bandwidth, at_s: 100000}\n  - {kind: tcp_stall, on: {service: GET_CONFIG, nth: 1}}\n"));
  EXPECT_EQ(std::count(plain.begin(), plain.end(), '\n'), 8);
  EXPECT_EQ(plain.find("(nothing)"), std::string::npos) << plain;
  EXPECT_EQ(plain, dormant);
}

}  // namespace
}  // namespace ldoem::wire_faults::test
