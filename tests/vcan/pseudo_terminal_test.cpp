#include "ldoem/io/pseudo_terminal.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "ldoem/io/event_loop.hpp"
#include "ldoem/base/unique_fd.hpp"

namespace ldoem::io {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

class PseudoTerminalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/ldoem-pty-test.XXXXXX";
    ASSERT_NE(::mkdtemp(pattern), nullptr);
    folder_ = pattern;
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path folder_;
};

// Everything the terminal has received within `limit`, up to `count` bytes.
protocol::Bytes receive_bytes(PseudoTerminal& terminal, std::size_t count,
                              std::chrono::milliseconds limit) {
  protocol::Bytes all;
  auto loop = EventLoop::create();
  EXPECT_TRUE(loop);
  EXPECT_TRUE((*loop)->watch(terminal.fd(), Interest::readable, [&](Readiness) {
    auto received = terminal.receive();
    ASSERT_TRUE(received) << received.error().message();
    all.insert(all.end(), received->bytes.begin(), received->bytes.end());
    if (all.size() >= count) {
      (*loop)->stop();
    }
  }));
  EXPECT_TRUE((*loop)->run_for(limit));
  return all;
}

TEST_F(PseudoTerminalTest, BytesWrittenByThePeer_ArriveUnchanged) {
  auto terminal = PseudoTerminal::open();
  ASSERT_TRUE(terminal) << terminal.error().message();
  base::UniqueFd host(::open(terminal->peer_path().c_str(), O_RDWR | O_NOCTTY));
  ASSERT_TRUE(host.valid());
  // Raw mode: CR, LF, ^C, ^D, DEL and 8-bit bytes are data, not terminal controls.
  const protocol::Bytes sent{0x00, 0x0A, 0x0D, 0x03, 0x04, 0x7F, 0xFF, 0x11, 0x13, 0x05};
  ASSERT_EQ(::write(host.get(), sent.data(), sent.size()), static_cast<ssize_t>(sent.size()));
  EXPECT_EQ(receive_bytes(*terminal, sent.size(), 2s), sent);
}

TEST_F(PseudoTerminalTest, BytesSentToThePeer_ArriveUnchanged) {
  auto terminal = PseudoTerminal::open();
  ASSERT_TRUE(terminal) << terminal.error().message();
  base::UniqueFd host(::open(terminal->peer_path().c_str(), O_RDWR | O_NOCTTY));
  ASSERT_TRUE(host.valid());
  const protocol::Bytes sent{0x02, 0x0A, 0x0D, 0xFF};
  auto accepted = terminal->send(sent);
  ASSERT_TRUE(accepted) << accepted.error().message();
  EXPECT_EQ(*accepted, sent.size());
  protocol::Bytes got(sent.size());
  ASSERT_EQ(::read(host.get(), got.data(), got.size()), static_cast<ssize_t>(got.size()));
  EXPECT_EQ(got, sent);
}

TEST_F(PseudoTerminalTest, NothingWritten_ReceivesNothingWithoutHangUp) {
  auto terminal = PseudoTerminal::open();
  ASSERT_TRUE(terminal) << terminal.error().message();
  auto received = terminal->receive();
  ASSERT_TRUE(received) << received.error().message();
  EXPECT_TRUE(received->bytes.empty());
  EXPECT_FALSE(received->peer_closed);
}

TEST_F(PseudoTerminalTest, HostClosingThePeer_IsNotAHangUp) {
  auto terminal = PseudoTerminal::open();
  ASSERT_TRUE(terminal) << terminal.error().message();
  {
    base::UniqueFd host(::open(terminal->peer_path().c_str(), O_RDWR | O_NOCTTY));
    ASSERT_TRUE(host.valid());
  }
  auto loop = EventLoop::create();
  ASSERT_TRUE(loop);
  int wakeups = 0;
  ASSERT_TRUE((*loop)->watch(terminal->fd(), Interest::readable, [&](Readiness) { ++wakeups; }));
  ASSERT_TRUE((*loop)->run_for(30ms));
  EXPECT_EQ(wakeups, 0);
}

TEST_F(PseudoTerminalTest, Symlink_PointsAtThePeerAndIsRemovedOnClose) {
  const fs::path link = folder_ / "lpt";
  {
    auto terminal = PseudoTerminal::open(link);
    ASSERT_TRUE(terminal) << terminal.error().message();
    ASSERT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(fs::read_symlink(link), terminal->peer_path());
    base::UniqueFd host(::open(link.c_str(), O_RDWR | O_NOCTTY));
    ASSERT_TRUE(host.valid());
    ASSERT_EQ(::write(host.get(), "\x05", 1), 1);
    EXPECT_EQ(receive_bytes(*terminal, 1, 2s), protocol::Bytes{0x05});
  }
  EXPECT_FALSE(fs::exists(fs::symlink_status(link)));
}

TEST_F(PseudoTerminalTest, StaleSymlink_IsReplaced) {
  const fs::path link = folder_ / "lpt";
  fs::create_symlink("/dev/pts/does-not-exist", link);
  auto terminal = PseudoTerminal::open(link);
  ASSERT_TRUE(terminal) << terminal.error().message();
  EXPECT_EQ(fs::read_symlink(link), terminal->peer_path());
}

TEST_F(PseudoTerminalTest, RegularFileAtTheLinkPath_IsLeftAloneAndReported) {
  const fs::path link = folder_ / "lpt";
  std::ofstream(link) << "keep me";
  auto terminal = PseudoTerminal::open(link);
  ASSERT_FALSE(terminal);
  EXPECT_EQ(terminal.error().error_number, EEXIST);
  EXPECT_TRUE(fs::is_regular_file(link));
}

TEST_F(PseudoTerminalTest, MovedTerminal_RemovesTheLinkOnlyOnce) {
  const fs::path link = folder_ / "lpt";
  std::string peer;
  {
    auto terminal = PseudoTerminal::open(link);
    ASSERT_TRUE(terminal) << terminal.error().message();
    PseudoTerminal moved = std::move(*terminal);
    peer = moved.peer_path();
    EXPECT_TRUE(fs::is_symlink(link));
  }
  EXPECT_FALSE(fs::exists(fs::symlink_status(link)));
  EXPECT_FALSE(peer.empty());
}

}  // namespace
}  // namespace ldoem::io
