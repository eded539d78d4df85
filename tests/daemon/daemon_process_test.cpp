// ldoem-emud as a child process, driven only through its endpoints (qtest style, design.md convention 4):
// TCP conversation of spec 7.3 with byte-exact replies, hostile TCP clients, the serial pty,
// the LPT pty moving the tilt, exit codes, SIGTERM saving the flash, SIGUSR1 counters.
#include <fcntl.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <thread>

#include "daemon_process.hpp"
#include "host_link.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/test_support/raw_tty.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;
using test_support::open_raw;

// A daemon on an ephemeral TCP port, no CAN, flash in memory unless the test names one.
struct RunningDaemon {
  TempDir dir;
  std::optional<DaemonProcess> process;

  explicit RunningDaemon(std::vector<std::string> extra = {}, bool virtual_time = true) {
    const std::string scene = dir.write("scene.yaml", minimal_scene_text());
    std::vector<std::string> arguments{"--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0"};
    if (virtual_time) arguments.push_back("--virtual-time");
    if (std::find(extra.begin(), extra.end(), "--flash") == extra.end()) arguments.push_back("--no-flash");
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    arguments.push_back("--timeout");  // never outlive a broken test
    arguments.push_back("120");
    if (auto started = DaemonProcess::start(arguments)) process.emplace(std::move(*started));
  }
  bool ready() { return process && process->wait_ready(); }
};

// One request, one reply: the reply frame's bytes as hex.
std::string exchange(TcpHost& host, std::string_view request_text) {
  host.send(telegram(request_text));
  const auto frame = host.next_frame();
  return frame ? to_hex(*frame) : std::string("(no reply)");
}

std::string frame_hex(std::string_view payload_text) { return to_hex(protocol::encode_tcp_frame(telegram(payload_text))); }

TEST(DaemonTcp, S1Conversation_RepliesAreByteExact) {
  RunningDaemon daemon;
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto host = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(host);

  // Spec 7.3 steps 1..8, replies as spec 7.2 lists them (D3/D4 values where 7.2 shows others).
  EXPECT_EQ(exchange(*host, "GET_STATUS"), "02 55 53 50 00 00 00 06 81 02 00 00 00 01 82");
  for (const char* item : {"0000", "0001", "0002", "0003", "0004", "0010", "0011", "0012", "0020", "0021", "0022"}) {
    host->send(telegram(std::string("GET_IDENTIFICATION ") + item));
    const auto reply = host->next_payload();
    ASSERT_TRUE(reply) << item;
    ASSERT_GE(reply->size(), 2u);
    EXPECT_EQ(to_hex(protocol::ByteView(*reply).first(2)), "81 01") << item;
  }
  host->send(telegram("GET_IDENTIFICATION 0011"));  // D3: firmware name, no NUL or padding
  EXPECT_EQ(host->next_payload(), std::optional<Bytes>(Bytes{0x81, 0x01, 'l', 'd', 'o', 'e', 'm', '-', 'e', 'm', 'u', 'd'}));
  EXPECT_EQ(exchange(*host, "GET_CONFIG 0005"),
            "02 55 53 50 00 00 00 20 82 02 00 05 00 C0 00 A8 00 01 00 0A 00 FF 00 FF 00 FF 00 00 00 C0 00 A8 00 01 "
            "00 01 00 00 00 00 71");
  EXPECT_EQ(exchange(*host, "GET_CONFIG 0010"), frame_hex("GET_CONFIG reply 0010 0001 000a 0004"));  // D4
  EXPECT_EQ(exchange(*host, "GET_FUNCTION 0000"), frame_hex("GET_FUNCTION reply 0000 0003 0870"));
  EXPECT_EQ(exchange(*host, "GET_FUNCTION 0001"), frame_hex("GET_FUNCTION reply 0001 0001 0e10"));
  EXPECT_EQ(exchange(*host, "GET_FUNCTION 0002"), "02 55 53 50 00 00 00 08 82 0B 00 02 00 00 00 00 8B");
  EXPECT_EQ(exchange(*host, "SET_SIGNAL 0000"), "02 55 53 50 00 00 00 04 81 05 00 00 84");
  EXPECT_EQ(exchange(*host, "TRANS_ROTATE 0000"), "02 55 53 50 00 00 00 06 84 03 00 00 00 02 85");
  EXPECT_EQ(exchange(*host, "TRANS_MEASURE"), "02 55 53 50 00 00 00 08 84 04 00 00 00 03 00 00 83");

  // Step 9: a stream of 0x39FF profiles, sent counting from 1, SENSTAT MEASURE/OK.
  host->send(telegram("GET_PROFILE 0000 39ff"));
  for (std::uint16_t expected_sent = 1; expected_sent <= 3; ++expected_sent) {
    const auto payload = host->next_payload();
    ASSERT_TRUE(payload);
    const auto profile = protocol::decode_profile(*payload);
    ASSERT_TRUE(profile) << to_hex(*payload);
    EXPECT_EQ(profile->format, 0x39FF);
    EXPECT_EQ(profile->profile_sent, expected_sent);
    EXPECT_EQ(to_hex(protocol::ByteView(*payload).last(1)), "03");  // SENSTAT byte 3: MEASURE, motor OK
  }
  // Step 10: CANCEL_PROFILE; profiles queued before it may still arrive, none after its reply (D10).
  host->send(telegram("CANCEL_PROFILE"));
  std::string reply;
  for (int i = 0; i < 100000 && reply.empty(); ++i) {
    const auto frame = host->next_frame();
    ASSERT_TRUE(frame);
    if ((*frame)[8] != 0x83 || (*frame)[9] != 0x01) reply = to_hex(*frame);
  }
  EXPECT_EQ(reply, "02 55 53 50 00 00 00 06 83 02 00 00 00 03 82");
  EXPECT_EQ(exchange(*host, "TRANS_ROTATE 0000"), "02 55 53 50 00 00 00 06 84 03 00 00 00 02 85");
  EXPECT_EQ(exchange(*host, "TRANS_IDLE"), "02 55 53 50 00 00 00 06 84 02 00 00 00 01 87");
  EXPECT_EQ(exchange(*host, "SET_SIGNAL 0000"), "02 55 53 50 00 00 00 04 81 05 00 00 84");
  EXPECT_FALSE(host->next_frame(300ms).has_value());  // nothing unasked for
}

TEST(DaemonTcp, GarbageAndBadChecksum_AnsweredFramingFailureAndDaemonStaysUp) {
  RunningDaemon daemon;
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto host = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(host);
  host->send_raw(hex("DE AD BE EF 00 11 02 55"));                 // garbage: skipped silently
  host->send_raw(hex("02 55 53 50 00 00 00 02 01 02 FF"));        // GET_STATUS, checksum wrong
  EXPECT_EQ(to_hex(*host->next_frame()), frame_hex("SERVICE_FAILURE 0102 0005"));  // D2 reason 5
  EXPECT_EQ(exchange(*host, "GET_STATUS"), "02 55 53 50 00 00 00 06 81 02 00 00 00 01 82");
  EXPECT_EQ(exchange(*host, "0500 0001"), frame_hex("SERVICE_FAILURE 0500 0001"));  // D2 reason 1
}

TEST(DaemonTcp, HalfOpenClient_DoesNotBlockOthers) {
  RunningDaemon daemon;
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto stalled = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(stalled);
  stalled->send_raw(hex("02 55 53 50 00 00 00 02 01"));  // a frame that never completes
  auto silent = TcpHost::connect(daemon.process->tcp_port());  // connects, never sends
  ASSERT_TRUE(silent);
  auto served = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(served);
  EXPECT_EQ(exchange(*served, "GET_STATUS"), "02 55 53 50 00 00 00 06 81 02 00 00 00 01 82");
  EXPECT_FALSE(stalled->next_frame(200ms).has_value());
}

TEST(DaemonTcp, ClientThatNeverReads_IsDroppedWhileOthersAreServed) {
  RunningDaemon daemon;
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto flooding = io::TcpConnection::connect("127.0.0.1", daemon.process->tcp_port());
  ASSERT_TRUE(flooding);
  auto served = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(served);
  // GET_STATUS requests, 11 bytes each, 15-byte replies nobody reads: the socket buffers fill,
  // then the daemon's bounded queue, then the daemon drops the connection.
  Bytes burst;
  for (int i = 0; i < 4096; ++i) {
    const Bytes frame = protocol::encode_tcp_frame(telegram("GET_STATUS"));
    burst.insert(burst.end(), frame.begin(), frame.end());
  }
  bool dropped = false;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  std::size_t total = 0;
  while (!dropped && std::chrono::steady_clock::now() < deadline) {
    auto sent = flooding->send(burst);
    if (!sent) {
      dropped = true;  // EPIPE / ECONNRESET: the daemon closed it
      break;
    }
    total += *sent;
    if (*sent == 0) std::this_thread::sleep_for(5ms);
    if (total % (burst.size() * 16) < burst.size()) {
      EXPECT_EQ(exchange(*served, "GET_STATUS"), "02 55 53 50 00 00 00 06 81 02 00 00 00 01 82");
    }
  }
  EXPECT_TRUE(dropped) << "sent " << total << " bytes without being dropped";
  EXPECT_EQ(exchange(*served, "GET_STATUS"), "02 55 53 50 00 00 00 06 81 02 00 00 00 01 82");
  daemon.process->signal(SIGUSR1);
  std::this_thread::sleep_for(300ms);
  EXPECT_NE(daemon.process->stderr_text().find("tcp_dropped_slow=1"), std::string::npos)
      << daemon.process->stderr_text();
}

TEST(DaemonTcp, StreamToAHostThatDoesNotRead_SkipsProfilesAndCountsThem) {
  RunningDaemon daemon;
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto host = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(host);
  exchange(*host, "TRANS_ROTATE 0000");
  exchange(*host, "TRANS_MEASURE");
  // Virtual time races ahead until the socket buffers are full. With the kernel's autotuned
  // send buffer that took 1 753 profiles, more than an ASan build on a busy machine measures in
  // 60 s (~6 a second, issue 23). The daemon now fixes its send buffer (io::kTcpSendBufferBytes,
  // L-time-2) and the host's receive buffer is at its minimum, so the first skip comes after a
  // few dozen profiles on any machine.
  const int receive_buffer = 4096;
  ASSERT_EQ(::setsockopt(host->fd(), SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer), 0);
  host->send(telegram("GET_PROFILE 0000 39ff"));
  std::uint64_t skipped = 0;
  std::string text;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (skipped == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(500ms);
    daemon.process->signal(SIGUSR1);
    std::this_thread::sleep_for(200ms);
    text = daemon.process->stderr_text();
    const auto at = text.rfind("skipped_profiles=");
    if (at != std::string::npos) skipped = std::stoull(text.substr(at + 17));
  }
  ASSERT_GT(skipped, 0u) << text;  // D10
  const auto sent_at = text.rfind("profiles_sent=");
  ASSERT_NE(sent_at, std::string::npos) << text;
  // Bounded by the buffers, not by the machine's speed: the daemon's 64 KiB send buffer and the
  // host's window take some 30 to 90 profiles (34 measured; 1 753 with the kernel's 4 MiB).
  EXPECT_LT(std::stoull(text.substr(sent_at + 14)), 150u) << text;
  // What does arrive is consecutive in PROFILESENT with gaps in PROFILECOUNT.
  std::uint16_t last_sent = 0;
  std::uint16_t last_count = 0;
  bool count_jumped = false;
  // The socket buffers hold many profiles from before the first skip: read until the gap.
  for (int i = 0; i < 50000 && !count_jumped; ++i) {
    const auto payload = host->next_payload();
    ASSERT_TRUE(payload);
    const auto profile = protocol::decode_profile(*payload);
    ASSERT_TRUE(profile);
    if (last_sent != 0) {
      EXPECT_EQ(profile->profile_sent, static_cast<std::uint16_t>(last_sent + 1));
      count_jumped |= profile->profile_count != static_cast<std::uint16_t>(last_count + 1);
    }
    last_sent = profile->profile_sent;
    last_count = profile->profile_count;
  }
  EXPECT_TRUE(count_jumped);
}

TEST(DaemonTcp, TwoConnections_ProfilesGoOnlyToTheOneThatAsked) {
  RunningDaemon daemon;
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto asking = TcpHost::connect(daemon.process->tcp_port());
  auto other = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(asking && other);
  exchange(*asking, "TRANS_ROTATE 0000");
  exchange(*asking, "TRANS_MEASURE");
  asking->send(telegram("GET_PROFILE 0002 39ff"));
  ASSERT_TRUE(asking->next_payload());
  ASSERT_TRUE(asking->next_payload());
  EXPECT_EQ(exchange(*other, "GET_STATUS"), "02 55 53 50 00 00 00 06 81 02 00 00 00 03 80");  // D10
}

// --------------------------------------------------------------------------------------- serial

TEST(DaemonSerial, S2GetStatus_IsAnsweredAsOnePackage) {
  TempDir dir;
  const std::string scene = dir.write("scene.yaml", minimal_scene_text());
  auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--serial", "serial:pty:" + dir.path("serial"),
                                       "--no-flash", "--virtual-time", "--timeout", "120"});
  ASSERT_TRUE(process && process->wait_ready()) << (process ? process->stderr_text() : "");
  const int fd = open_raw(dir.path("serial"));
  ASSERT_GE(fd, 0);
  const std::string request = "\x02" "00100003000001026d36" "\x03";  // spec 7.4
  ASSERT_EQ(::write(fd, request.data(), request.size()), static_cast<ssize_t>(request.size()));
  const Bytes expected = protocol::encode_serial_reply(telegram("GET_STATUS reply 0000 0001"));
  Bytes received;
  while (received.size() < expected.size() && wait_readable(fd, 5s)) {
    std::uint8_t buffer[256];
    const ssize_t count = ::read(fd, buffer, sizeof buffer);
    if (count <= 0) break;
    received.insert(received.end(), buffer, buffer + count);
  }
  EXPECT_EQ(to_hex(received), to_hex(expected));
  // A bad CRC is a framing error, answered SERVICE_FAILURE reason 5 (D2).
  const std::string corrupt = "\x02" "00100003000001026d37" "\x03";
  ASSERT_EQ(::write(fd, corrupt.data(), corrupt.size()), static_cast<ssize_t>(corrupt.size()));
  protocol::SerialReplyReassembler reassembler;
  std::optional<Bytes> failure;
  while (!failure && wait_readable(fd, 5s)) {
    std::uint8_t buffer[256];
    const ssize_t count = ::read(fd, buffer, sizeof buffer);
    if (count <= 0) break;
    for (const auto& event : reassembler.feed(protocol::ByteView(buffer, static_cast<std::size_t>(count)))) {
      if (const auto* telegram_event = std::get_if<protocol::Telegram>(&event)) failure = telegram_event->payload;
    }
  }
  EXPECT_EQ(failure, std::optional<Bytes>(telegram("SERVICE_FAILURE 0102 0005")));
  ::close(fd);
}

// ------------------------------------------------------------------------------------------ LPT

// The distance of the beam at head angle 0 (+x, D5) in one single-profile GET_PROFILE.
std::optional<std::uint16_t> distance_ahead(TcpHost& host) {
  host.send(telegram("GET_PROFILE 0001 39ff"));
  const auto payload = host.next_payload();
  if (!payload) return std::nullopt;
  const auto profile = protocol::decode_profile(*payload);
  EXPECT_TRUE(profile) << to_hex(*payload);
  if (!profile) return std::nullopt;
  return distance_at_angle_zero(*profile);
}

TEST(DaemonLpt, StepsWrittenToThePty_TiltTheBeamInLaterProfiles) {
  TempDir lpt_dir;
  RunningDaemon daemon({"--lpt", "lpt:pty:" + lpt_dir.path("lpt")});
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto host = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(host);
  exchange(*host, "TRANS_ROTATE 0000");
  exchange(*host, "TRANS_MEASURE");
  EXPECT_EQ(distance_ahead(*host), std::optional<std::uint16_t>(1280));  // level: 5 m

  const int fd = open_raw(lpt_dir.path("lpt"));
  ASSERT_GE(fd, 0);
  Bytes register_writes;  // D8: 200 full steps with DIR = 1: 18 deg up
  for (int i = 0; i < 200; ++i) {
    register_writes.push_back(0x01);
    register_writes.push_back(0x03);
  }
  ASSERT_EQ(::write(fd, register_writes.data(), register_writes.size()), static_cast<ssize_t>(register_writes.size()));
  std::this_thread::sleep_for(300ms);  // let the daemon read the pty before asking
  const auto tilted = distance_ahead(*host);
  ASSERT_TRUE(tilted);
  EXPECT_NEAR(*tilted, 5.0 / std::cos(18.0 * std::numbers::pi / 180.0) * 256.0, 1.0);  // 5.257 m
  ::close(fd);
  daemon.process->signal(SIGUSR1);
  std::this_thread::sleep_for(300ms);
  EXPECT_NE(daemon.process->stderr_text().find("lpt_steps=200"), std::string::npos) << daemon.process->stderr_text();
}

// ---------------------------------------------------------------------------- exit codes, flash

TEST(DaemonExit, BadScene_ExitsTwoWithFileLineColumn) {
  TempDir dir;
  const std::string scene = dir.write("bad.yaml", "objects:\n  - name: wall\n    bx: {size_m: [1, 1, 1]}\n");
  auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash"});
  ASSERT_TRUE(process);
  EXPECT_EQ(process->wait(), std::optional<int>(2));
  const std::string text = process->stderr_text();
  // The loader's file:line:col of the offending node (the object without a shape, line 2 col 5).
  EXPECT_NE(text.find("bad.yaml:2:5: objects[0]"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;  // one line
}

TEST(DaemonExit, UsageError_ExitsTwo) {
  auto process = DaemonProcess::start({"--scene", "x.yaml", "--time-scale", "0"});
  ASSERT_TRUE(process);
  EXPECT_EQ(process->wait(), std::optional<int>(2));
  EXPECT_NE(process->stderr_text().find("--time-scale"), std::string::npos);
}

TEST(DaemonExit, HelpAndVersion_ExitZero) {
  // --help-all is the full text (--help one screen of it, without the exit statuses).
  auto help = DaemonProcess::start({"--help-all"});
  ASSERT_TRUE(help);
  help->wait_ready(5s);  // collects stdout until exit
  EXPECT_EQ(help->wait(), std::optional<int>(0));
  EXPECT_NE(help->stdout_text().find("Exit status"), std::string::npos);
  auto version = DaemonProcess::start({"--version"});
  ASSERT_TRUE(version);
  version->wait_ready(5s);
  EXPECT_EQ(version->wait(), std::optional<int>(0));
  EXPECT_NE(version->stdout_text().find("ldoem-emud "), std::string::npos);
}

TEST(DaemonExit, MissingCanInterface_StopsStartUpWithOneLine) {
  TempDir dir;
  const std::string scene = dir.write("scene.yaml", minimal_scene_text());
  auto process = DaemonProcess::start({"--scene", scene, "--can", "can:nosuchcan0", "--no-flash"});
  ASSERT_TRUE(process);
  EXPECT_EQ(process->wait(), std::optional<int>(2));
  const std::string text = process->stderr_text();
  EXPECT_NE(text.find("nosuchcan0"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  // A kernel without CAN says so and what to do (issue 24), not "does not exist".
  if (text.find("Address family not supported") != std::string::npos) {
    EXPECT_NE(text.find("modprobe vcan"), std::string::npos) << text;
    EXPECT_NE(text.find("docs/uml-harness.md"), std::string::npos) << text;
  }
}

TEST(DaemonExit, CountProfiles_StopsWithExitZero) {
  RunningDaemon daemon({"--count-profiles", "2"});
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto host = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(host);
  exchange(*host, "TRANS_ROTATE 0000");
  exchange(*host, "TRANS_MEASURE");
  host->send(telegram("GET_PROFILE 0000 39ff"));
  EXPECT_EQ(daemon.process->wait(), std::optional<int>(0)) << daemon.process->stderr_text();
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(DaemonExit, Sigterm_SavesFlashAndExits143_AndTheFlashSurvivesARestart) {
  TempDir flash_dir;
  const std::string flash = flash_dir.path("scene.flash");
  {
    RunningDaemon daemon({"--flash", flash});
    ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
    auto host = TcpHost::connect(daemon.process->tcp_port());
    ASSERT_TRUE(host);
    // SET_FUNCTION sector 0 normal to 90 deg, written to flash (flash flag 1).
    host->send(telegram("SET_FUNCTION 0000 0003 05a0 0001"));
    ASSERT_TRUE(host->next_payload());
    daemon.process->signal(SIGTERM);
    EXPECT_EQ(daemon.process->wait(), std::optional<int>(128 + SIGTERM));
  }
  const std::string image = read_file(flash);
  EXPECT_EQ(image.rfind("ldoem-flash 1\n", 0), 0u) << image;
  EXPECT_NE(image.find("sector 0 3 1440\n"), std::string::npos) << image;

  RunningDaemon restarted({"--flash", flash});
  ASSERT_TRUE(restarted.ready()) << restarted.process->stderr_text();
  auto host = TcpHost::connect(restarted.process->tcp_port());
  ASSERT_TRUE(host);
  EXPECT_EQ(exchange(*host, "GET_FUNCTION 0000"), frame_hex("GET_FUNCTION reply 0000 0003 05a0"));
  restarted.process->signal(SIGINT);
  EXPECT_EQ(restarted.process->wait(), std::optional<int>(128 + SIGINT));
}

TEST(DaemonLog, InfoLevel_LogsEachRequestAndReplyInTextForm) {
  RunningDaemon daemon({"--log-level", "info"});
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto host = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(host);
  exchange(*host, "GET_STATUS");
  std::this_thread::sleep_for(200ms);
  const std::string text = daemon.process->stderr_text();
  EXPECT_NE(text.find("tcp#1 -> GET_STATUS\n"), std::string::npos) << text;
  EXPECT_NE(text.find("tcp#1 <- GET_STATUS reply 0000 0001\n"), std::string::npos) << text;
}

}  // namespace
}  // namespace ldoem::daemon::test

namespace ldoem::daemon::test {
namespace {

TEST(DaemonTime, ScaledClock_SpinUpAndProfilesComeOnWallDeadlines) {
  RunningDaemon daemon({"--time-scale", "20"}, /*virtual_time=*/false);  // D7: 2 s spin-up in 0.1 s
  ASSERT_TRUE(daemon.ready()) << daemon.process->stderr_text();
  auto host = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(host);
  EXPECT_EQ(exchange(*host, "TRANS_ROTATE 0000"), "02 55 53 50 00 00 00 06 84 03 00 00 00 02 85");
  EXPECT_EQ(exchange(*host, "TRANS_MEASURE"), "02 55 53 50 00 00 00 08 84 04 00 00 00 03 00 00 83");
  EXPECT_EQ(distance_ahead(*host), std::optional<std::uint16_t>(1280));
}

}  // namespace
}  // namespace ldoem::daemon::test
