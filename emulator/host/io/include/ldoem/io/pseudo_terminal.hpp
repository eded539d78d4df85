// A pseudo-terminal whose peer side plays a serial port or the LPT byte stream (D8 pty back end):
// the host program opens peer_path() (or the symlink, e.g. /tmp/ldoem-lpt) and every byte it
// writes arrives here unchanged (raw mode), and vice versa.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "ldoem/io/byte_stream.hpp"
#include "ldoem/io/io_error.hpp"
#include "ldoem/base/unique_fd.hpp"

namespace ldoem::io {

class PseudoTerminal {
 public:
  // posix_openpt + grantpt + unlockpt, raw mode (cfmakeraw), non-blocking, close-on-exec. With
  // `link_path`, a symlink to the peer device is created there (replacing a stale symlink, never
  // a regular file) and removed again on destruction if it still points at this terminal.
  static IoResult<PseudoTerminal> open(std::optional<std::filesystem::path> link_path = {});

  PseudoTerminal(PseudoTerminal&& other) noexcept;
  PseudoTerminal& operator=(PseudoTerminal&& other) noexcept;
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;
  ~PseudoTerminal();

  // Bytes the peer wrote (at most max_bytes); empty when none are waiting. The peer side is
  // kept open by this object too, so a host closing and reopening it is not a hang-up.
  IoResult<Received> receive(std::size_t max_bytes = 4096);
  // How many leading bytes of `bytes` the terminal took (0 when its buffer is full). ECHO is
  // switched off first if the host switched it on: it would feed our bytes back to us.
  IoResult<std::size_t> send(protocol::ByteView bytes);
  // How often send() found ECHO on and switched it off.
  std::uint64_t echo_resets() const { return echo_resets_; }

  int fd() const { return controller_.get(); }
  const std::string& peer_path() const { return peer_path_; }  // e.g. /dev/pts/3
  const std::optional<std::filesystem::path>& link_path() const { return link_path_; }

 private:
  PseudoTerminal() = default;
  void remove_link();
  void keep_echo_off();

  base::UniqueFd controller_;    // the master side, ours
  base::UniqueFd peer_keeper_;   // our own open of the peer side: no EPOLLHUP while the host is away
  std::string peer_path_;
  std::optional<std::filesystem::path> link_path_;
  std::uint64_t echo_resets_ = 0;
};

}  // namespace ldoem::io
