// A pseudo-terminal pair for serial and LPT tests: the test holds the master, the code under
// test opens the slave by path.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <string>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::driver::test {

class PtyPair {
 public:
  PtyPair() {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0) {
      throw std::runtime_error("test pty: cannot open a pseudo terminal");
    }
    char name[128];
    if (::ptsname_r(master_, name, sizeof name) != 0) {
      throw std::runtime_error("test pty: ptsname_r failed");
    }
    slave_path_ = name;
    // Raw on the slave side from the start, so that what the test writes arrives verbatim even
    // before the code under test opens the slave.
    const int slave = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
    termios settings{};
    ::tcgetattr(slave, &settings);
    ::cfmakeraw(&settings);
    ::tcsetattr(slave, TCSANOW, &settings);
    keep_slave_open_ = slave;
  }
  ~PtyPair() {
    ::close(master_);
    ::close(keep_slave_open_);
  }
  PtyPair(const PtyPair&) = delete;
  PtyPair& operator=(const PtyPair&) = delete;

  const std::string& slave_path() const { return slave_path_; }

  void write_master(const protocol::Bytes& bytes) const {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t written = ::write(master_, bytes.data() + done, bytes.size() - done);
      if (written <= 0) {
        throw std::runtime_error("test pty: write failed");
      }
      done += static_cast<std::size_t>(written);
    }
  }

  // Reads until `count` bytes arrived or nothing came for `idle_ms`.
  protocol::Bytes read_master(std::size_t count, int idle_ms = 2000) const {
    protocol::Bytes out;
    while (out.size() < count) {
      pollfd entry{master_, POLLIN, 0};
      if (::poll(&entry, 1, idle_ms) <= 0) {
        break;
      }
      std::uint8_t buffer[512];
      const ssize_t got = ::read(master_, buffer, std::min(sizeof buffer, count - out.size()));
      if (got <= 0) {
        break;
      }
      out.insert(out.end(), buffer, buffer + got);
    }
    return out;
  }

  // Closes our extra slave descriptor, so that closing the master hangs the line up.
  void close_master() {
    ::close(keep_slave_open_);
    keep_slave_open_ = -1;
    ::close(master_);
    master_ = -1;
  }

 private:
  int master_ = -1;
  int keep_slave_open_ = -1;
  std::string slave_path_;
};

}  // namespace ldoem::driver::test
