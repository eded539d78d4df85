// ldoem-emud's TCP endpoint (spec 4.1) against hostile clients: random bytes, fake headers with
// huge lengths, half-open and half-closed connections, a client that reads one byte per 100 ms
// from a profile stream, connections reset at once. Each test ends with the daemon alive, its
// memory bounded and a correct request answered correctly on a fresh connection.
// (tests/daemon covers one half-open client, one client that never reads and a bad checksum.)
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "robustness.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

// A plain blocking socket to the daemon, for clients that misbehave below TcpHost's level.
int raw_connect(std::uint16_t port, int receive_buffer_bytes = 0) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  if (receive_buffer_bytes > 0) {
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof receive_buffer_bytes);
  }
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

bool send_all(int fd, protocol::ByteView bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t count = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (count <= 0) return false;  // the daemon may close a connection it finds hopeless
    sent += static_cast<std::size_t>(count);
  }
  return true;
}

// The correct request at the end of every test, on a fresh connection: the exact reply.
::testing::AssertionResult served_correctly(std::uint16_t port) {
  auto host = TcpHost::connect(port);
  if (!host) return ::testing::AssertionFailure() << "cannot connect";
  host->send(telegram("GET_IDENTIFICATION 0011"));
  const auto reply = host->next_payload();
  const Bytes expected{0x81, 0x01, 'l', 'd', 'o', 'e', 'm', '-', 'e', 'm', 'u', 'd'};  // D3 firmware name
  if (reply != std::optional<Bytes>(expected)) {
    return ::testing::AssertionFailure() << "reply " << (reply ? to_hex(*reply) : "(none)");
  }
  return ::testing::AssertionSuccess();
}

HostileRun tcp_daemon() { return HostileRun({"--no-can", "--tcp", "tcp:127.0.0.1:0", "--virtual-time"}); }

TEST(TcpRobustness, RandomBytesOnEightConnections_DaemonServesTheNextHost) {
  HostileRun daemon = tcp_daemon();
  ASSERT_TRUE(daemon.ready());
  const std::uint16_t port = daemon.process->tcp_port();
  std::mt19937_64 generator(0x5EED0001);
  std::vector<int> fds;
  for (int connection = 0; connection < 8; ++connection) {
    const int fd = raw_connect(port);
    ASSERT_GE(fd, 0);
    fds.push_back(fd);
    for (int chunk = 0; chunk < 64; ++chunk) {  // 8 x 64 x 8 KiB = 4 MiB of noise
      if (!send_all(fd, random_bytes(generator, 8192))) break;
    }
  }
  EXPECT_TRUE(served_correctly(port));
  EXPECT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
  for (const int fd : fds) ::close(fd);
}

TEST(TcpRobustness, FakeHeadersWithHugeLengths_AreDroppedAndTheSameConnectionRecovers) {
  HostileRun daemon = tcp_daemon();
  ASSERT_TRUE(daemon.ready());
  auto host = TcpHost::connect(daemon.process->tcp_port());
  ASSERT_TRUE(host);
  // Lengths of 4 GiB - 1, 2 GiB, 16 MiB and 5817 (one above spec 4.1's 5816), each followed by
  // a little payload: nothing may be allocated for them, and the deframer must hunt on.
  for (const char* header : {"02 55 53 50 FF FF FF FF", "02 55 53 50 80 00 00 00", "02 55 53 50 01 00 00 00",
                             "02 55 53 50 00 00 16 B9"}) {
    host->send_raw(hex(header));
    host->send_raw(hex("01 02 03 04 05 06 07 08"));
  }
  host->send(telegram("GET_IDENTIFICATION 0011"));
  const Bytes failure = telegram("SERVICE_FAILURE 0000 0000");
  const Bytes failure_code(failure.begin(), failure.begin() + 2);
  std::optional<Bytes> answer;
  for (int frames = 0; frames < 16 && !answer; ++frames) {
    const auto payload = host->next_payload();
    ASSERT_TRUE(payload) << "no reply after the fake headers";
    if (payload->size() >= 2 && Bytes(payload->begin(), payload->begin() + 2) == failure_code) continue;  // D2 reason 5
    answer = payload;
  }
  EXPECT_EQ(answer, std::optional<Bytes>(Bytes{0x81, 0x01, 'l', 'd', 'o', 'e', 'm', '-', 'e', 'm', 'u', 'd'}));
  // A header that promises 4 GiB and a peer that goes away mid-frame.
  const int fd = raw_connect(daemon.process->tcp_port());
  ASSERT_GE(fd, 0);
  send_all(fd, hex("02 55 53 50 FF FF FF F0 00 00 00"));
  ::close(fd);
  EXPECT_TRUE(served_correctly(daemon.process->tcp_port()));
  EXPECT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
}

// 122 connections at once: --max-clients is raised above its default of 64 so that this test
// is about the event loop (no connection may stall the others), not about the limit.
TEST(TcpRobustness, HalfOpenHalfClosedAndSlowClients_DoNotStopAnotherHostBeingServed) {
  HostileRun daemon({"--no-can", "--tcp", "tcp:127.0.0.1:0", "--virtual-time", "--max-clients", "256"});
  ASSERT_TRUE(daemon.ready());
  const std::uint16_t port = daemon.process->tcp_port();
  std::vector<int> idle;
  for (int i = 0; i < 100; ++i) {  // frames that never complete, peers that never read
    const int fd = raw_connect(port);
    ASSERT_GE(fd, 0);
    send_all(fd, i % 2 == 0 ? hex("02 55 53") : hex("02 55 53 50 00 00 00 04 01 02"));
    idle.push_back(fd);
  }
  for (int i = 0; i < 20; ++i) {  // half-closed: a partial frame, then FIN, socket kept
    const int fd = raw_connect(port);
    ASSERT_GE(fd, 0);
    send_all(fd, hex("02 55 53 50 00 00 00 02 01"));
    ::shutdown(fd, SHUT_WR);
    idle.push_back(fd);
  }
  // A slow host: starts a profile stream, then reads one byte per 100 ms (D10: its profiles
  // are skipped while its queue is not empty, or it is dropped once the queue is over its bound).
  const int slow = raw_connect(port, 4096);
  ASSERT_GE(slow, 0);
  ASSERT_TRUE(send_all(slow, protocol::encode_tcp_frame(telegram("TRANS_ROTATE 0000"))));
  ASSERT_TRUE(send_all(slow, protocol::encode_tcp_frame(telegram("TRANS_MEASURE"))));
  ASSERT_TRUE(send_all(slow, protocol::encode_tcp_frame(telegram("GET_PROFILE 0000 39ff"))));
  std::atomic<bool> stop{false};
  std::atomic<std::size_t> slow_bytes{0};
  std::thread slow_reader([&] {
    while (!stop) {
      std::uint8_t byte;
      if (::recv(slow, &byte, 1, MSG_DONTWAIT) == 1) ++slow_bytes;
      std::this_thread::sleep_for(100ms);
    }
  });
  for (int round = 0; round < 40; ++round) {  // about 4 s of the slow reader
    ASSERT_TRUE(served_correctly(port)) << "round " << round;
    std::this_thread::sleep_for(100ms);
  }
  stop = true;
  slow_reader.join();
  EXPECT_GT(slow_bytes.load(), 0u);
  EXPECT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
  ::close(slow);
  for (const int fd : idle) ::close(fd);
  EXPECT_TRUE(served_correctly(port));
  EXPECT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
}

// --max-clients 2: the third host's connection is accepted and closed at once (EOF, no reply:
// the protocol has no busy telegram), the two served go on, and a place comes back when one goes.
TEST(TcpRobustness, MaxClients_TheNextHostIsClosedAndTheOthersAreServed) {
  HostileRun daemon({"--no-can", "--tcp", "tcp:127.0.0.1:0", "--virtual-time", "--max-clients", "2"});
  ASSERT_TRUE(daemon.ready());
  const std::uint16_t port = daemon.process->tcp_port();
  auto first = TcpHost::connect(port);
  auto second = TcpHost::connect(port);
  ASSERT_TRUE(first && second);
  first->send(telegram("GET_STATUS"));  // both are in before the third connects
  second->send(telegram("GET_STATUS"));
  ASSERT_TRUE(first->next_payload() && second->next_payload());
  const int third = raw_connect(port);
  ASSERT_GE(third, 0);
  send_all(third, protocol::encode_tcp_frame(telegram("GET_STATUS")));
  pollfd closed{third, POLLIN, 0};
  ASSERT_EQ(::poll(&closed, 1, 5000), 1) << "the third connection was neither answered nor closed";
  std::uint8_t byte;
  EXPECT_LE(::recv(third, &byte, 1, 0), 0);  // EOF or reset, never a reply
  ::close(third);
  first->send(telegram("GET_STATUS"));
  EXPECT_TRUE(first->next_payload());
  first.reset();
  EXPECT_TRUE(served_correctly(port));
  EXPECT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
}

TEST(TcpRobustness, ThreeHundredConnectionsReset_LeaveNothingBehind) {
  HostileRun daemon = tcp_daemon();
  ASSERT_TRUE(daemon.ready());
  const std::uint16_t port = daemon.process->tcp_port();
  for (int i = 0; i < 300; ++i) {
    const int fd = raw_connect(port);
    ASSERT_GE(fd, 0);
    if (i % 3 == 0) send_all(fd, protocol::encode_tcp_frame(telegram("GET_STATUS")));  // reply to a peer gone
    const linger reset{1, 0};  // close with RST instead of FIN
    ::setsockopt(fd, SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
    ::close(fd);
  }
  EXPECT_TRUE(served_correctly(port));
  EXPECT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
  // Its descriptors were closed: the daemon holds the listener, the epoll/signal/timer fds and
  // the one connection above at most, far below 300.
  const auto fds = std::distance(std::filesystem::directory_iterator("/proc/" + std::to_string(daemon.process->pid()) + "/fd"),
                                 std::filesystem::directory_iterator());
  EXPECT_LT(fds, 40);
}

}  // namespace
}  // namespace ldoem::daemon::test
