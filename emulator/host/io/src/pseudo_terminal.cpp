#include "ldoem/io/pseudo_terminal.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <system_error>

namespace ldoem::io {
namespace {

IoResult<std::string> peer_name_of(int controller_fd) {
  std::array<char, 128> name{};
  if (const int error = ::ptsname_r(controller_fd, name.data(), name.size()); error != 0) {
    return io_failure(IoError{"ptsname_r", {}, error, {}});
  }
  return std::string(name.data());
}

IoStatus make_raw(int fd, const std::string& path) {
  termios settings{};
  if (::tcgetattr(fd, &settings) != 0) {
    return io_failure(last_system_error("tcgetattr", path));
  }
  // D8 and the serial framing need every byte as written: no echo, no line editing, no CR/LF
  // translation, 8 bits.
  ::cfmakeraw(&settings);
  if (::tcsetattr(fd, TCSANOW, &settings) != 0) {
    return io_failure(last_system_error("tcsetattr", path));
  }
  return Done{};
}

IoStatus place_link(const std::filesystem::path& link, const std::string& target) {
  struct stat existing {};
  if (::lstat(link.c_str(), &existing) == 0 && !S_ISLNK(existing.st_mode)) {
    return io_failure(IoError{"symlink", link.string(), EEXIST,
                              "exists and is not a symlink; refusing to replace it"});
  }
  // Create beside it and rename over it: a reader never sees the link missing or half made.
  const std::filesystem::path temporary = link.string() + ".tmp" + std::to_string(::getpid());
  (void)::unlink(temporary.c_str());
  if (::symlink(target.c_str(), temporary.c_str()) != 0) {
    return io_failure(last_system_error("symlink", temporary.string()));
  }
  if (::rename(temporary.c_str(), link.c_str()) != 0) {
    IoError error = last_system_error("rename", link.string());
    (void)::unlink(temporary.c_str());
    return io_failure(error);
  }
  return Done{};
}

}  // namespace

IoResult<PseudoTerminal> PseudoTerminal::open(std::optional<std::filesystem::path> link_path) {
  PseudoTerminal terminal;
  terminal.controller_.reset(::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC));
  if (!terminal.controller_.valid()) {
    return io_failure(last_system_error("posix_openpt"));
  }
  const int controller = terminal.controller_.get();
  if (::grantpt(controller) != 0) {
    return io_failure(last_system_error("grantpt"));
  }
  if (::unlockpt(controller) != 0) {
    return io_failure(last_system_error("unlockpt"));
  }
  auto peer_name = peer_name_of(controller);
  if (!peer_name) {
    return io_failure(peer_name.error());
  }
  terminal.peer_path_ = *peer_name;
  terminal.peer_keeper_.reset(
      ::open(terminal.peer_path_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK));
  if (!terminal.peer_keeper_.valid()) {
    return io_failure(last_system_error("open", terminal.peer_path_));
  }
  if (IoStatus raw = make_raw(terminal.peer_keeper_.get(), terminal.peer_path_); !raw) {
    return io_failure(raw.error());
  }
  const int flags = ::fcntl(controller, F_GETFL);
  if (flags < 0 || ::fcntl(controller, F_SETFL, flags | O_NONBLOCK) != 0) {
    return io_failure(last_system_error("fcntl O_NONBLOCK", terminal.peer_path_));
  }
  if (link_path) {
    if (IoStatus linked = place_link(*link_path, terminal.peer_path_); !linked) {
      return io_failure(linked.error());
    }
    terminal.link_path_ = std::move(link_path);
  }
  return terminal;
}

PseudoTerminal::PseudoTerminal(PseudoTerminal&& other) noexcept
    : controller_(std::move(other.controller_)),
      peer_keeper_(std::move(other.peer_keeper_)),
      peer_path_(std::move(other.peer_path_)),
      link_path_(std::exchange(other.link_path_, std::nullopt)),
      echo_resets_(other.echo_resets_) {}

PseudoTerminal& PseudoTerminal::operator=(PseudoTerminal&& other) noexcept {
  if (this != &other) {
    remove_link();
    controller_ = std::move(other.controller_);
    peer_keeper_ = std::move(other.peer_keeper_);
    peer_path_ = std::move(other.peer_path_);
    link_path_ = std::exchange(other.link_path_, std::nullopt);
    echo_resets_ = other.echo_resets_;
  }
  return *this;
}

PseudoTerminal::~PseudoTerminal() { remove_link(); }

void PseudoTerminal::remove_link() {
  if (!link_path_) {
    return;
  }
  // Only our own link: another emulator may have taken the path over since.
  std::error_code error;
  const auto target = std::filesystem::read_symlink(*link_path_, error);
  if (!error && target == peer_path_) {
    std::filesystem::remove(*link_path_, error);
  }
  link_path_.reset();
}

IoResult<Received> PseudoTerminal::receive(std::size_t max_bytes) {
  Received received;
  received.bytes.resize(max_bytes);
  for (;;) {
    const ssize_t got = ::read(controller_.get(), received.bytes.data(), max_bytes);
    if (got >= 0) {
      received.bytes.resize(static_cast<std::size_t>(got));
      return received;
    }
    if (errno == EINTR) {
      continue;
    }
    received.bytes.clear();
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      return received;
    }
    return io_failure(last_system_error("read", peer_path_));
  }
}

// A host may switch its side back to a cooked mode with ECHO (`stty sane`, a terminal program):
// the line discipline then sends every byte we write straight back to us, and our replies come
// in as requests whose replies come back again, without end (issue 11). Before each write, ECHO
// and ECHONL are switched off again; the rest of the host's settings stay its own business.
void PseudoTerminal::keep_echo_off() {
  termios settings{};
  if (::tcgetattr(controller_.get(), &settings) != 0) return;
  if ((settings.c_lflag & (ECHO | ECHONL)) == 0) return;
  settings.c_lflag &= ~static_cast<tcflag_t>(ECHO | ECHONL);
  if (::tcsetattr(controller_.get(), TCSANOW, &settings) == 0) ++echo_resets_;
}

IoResult<std::size_t> PseudoTerminal::send(protocol::ByteView bytes) {
  keep_echo_off();
  for (;;) {
    const ssize_t written = ::write(controller_.get(), bytes.data(), bytes.size());
    if (written >= 0) {
      return static_cast<std::size_t>(written);
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      return std::size_t{0};
    }
    return io_failure(last_system_error("write", peer_path_));
  }
}

}  // namespace ldoem::io
