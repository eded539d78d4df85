// ldoem-emud's serial endpoint (spec 4.2, a pty) against line noise: random bytes, STX without
// ETX, endless hex. The daemon stays up, its memory bounded, and the next correct S2 request
// (spec 7.4) gets its exact one-package reply.
#include <fcntl.h>
#include <unistd.h>

#include "ldoem/test_support/raw_tty.hpp"
#include "robustness.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

// Writes everything, reading (and keeping) whatever the daemon answers meanwhile, so that
// neither side of the pty blocks on a full buffer.
void write_reading(int fd, protocol::ByteView bytes, Bytes& replies) {
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t count = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (count > 0) written += static_cast<std::size_t>(count);
    std::uint8_t buffer[4096];
    ssize_t got;
    while ((got = ::read(fd, buffer, sizeof buffer)) > 0) replies.insert(replies.end(), buffer, buffer + got);
    if (count <= 0) wait_readable(fd, 5ms);
  }
}

TEST(SerialRobustness, NoiseOnTheLine_ThenTheNextRequestGetsItsExactReply) {
  TempDir pty_dir;
  HostileRun daemon({"--no-can", "--serial", "serial:pty:" + pty_dir.path("serial"), "--virtual-time"});
  ASSERT_TRUE(daemon.ready());
  const int fd = test_support::open_raw(pty_dir.path("serial"), O_NONBLOCK);
  ASSERT_GE(fd, 0);
  std::mt19937_64 generator(0x5EED0002);
  Bytes replies;
  for (int chunk = 0; chunk < 256; ++chunk) {  // 1 MiB of random bytes
    write_reading(fd, random_bytes(generator, 4096), replies);
  }
  // An STX followed by 64 KiB of valid hex digits and no ETX (a package far over any length).
  Bytes endless{0x02};
  endless.insert(endless.end(), 65536, '3');
  write_reading(fd, endless, replies);
  write_reading(fd, hex("02 30 30 03 03 02 02"), replies);  // short, empty and doubled packages
  std::this_thread::sleep_for(200ms);
  replies.clear();
  std::uint8_t buffer[4096];
  while (::read(fd, buffer, sizeof buffer) > 0) {}  // answers to the noise are not checked

  const std::string request = "\x02" "00100003000001026d36" "\x03";  // spec 7.4 GET_STATUS
  write_reading(fd, protocol::ByteView(reinterpret_cast<const std::uint8_t*>(request.data()), request.size()), replies);
  const Bytes expected = protocol::encode_serial_reply(idle_status_reply());
  protocol::SerialReplyReassembler reassembler;
  std::optional<Bytes> status;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  std::size_t fed = 0;
  while (!status && std::chrono::steady_clock::now() < deadline) {
    for (const auto& event : reassembler.feed(protocol::ByteView(replies).subspan(fed))) {
      const auto* reply = std::get_if<protocol::Telegram>(&event);
      if (reply != nullptr && reply->payload == idle_status_reply()) status = reply->payload;
    }
    fed = replies.size();
    if (!status && wait_readable(fd, 50ms)) {
      const ssize_t got = ::read(fd, buffer, sizeof buffer);
      if (got > 0) replies.insert(replies.end(), buffer, buffer + got);
    }
  }
  EXPECT_EQ(status, std::optional<Bytes>(idle_status_reply())) << to_hex(replies);
  // Nothing but that reply (and possibly late answers to the noise) came; the reply is whole.
  EXPECT_NE(std::search(replies.begin(), replies.end(), expected.begin(), expected.end()), replies.end());
  EXPECT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
  ::close(fd);
}

}  // namespace
}  // namespace ldoem::daemon::test
