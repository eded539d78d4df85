#include "ldoem/driver/lpt_port.hpp"

#include <fcntl.h>
#include <linux/parport.h>
#include <linux/ppdev.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>

#include "fd_util.hpp"

namespace ldoem::driver {

// ------------------------------------------------------------------------------------ ppdev

Expected<std::unique_ptr<PpdevLptPort>, DriverError> PpdevLptPort::open(const std::string& path) {
  const std::string object = "lpt:" + path;
  base::UniqueFd fd(::open(path.c_str(), O_RDWR | O_CLOEXEC));
  if (!fd.valid()) {
    return fail(system_error("open", object, errno));
  }
  if (::ioctl(fd.get(), PPCLAIM) != 0) {
    return fail(system_error("PPCLAIM", object, errno));
  }
  return std::unique_ptr<PpdevLptPort>(new PpdevLptPort(fd.release(), object));
}

PpdevLptPort::~PpdevLptPort() {
  if (fd_ >= 0) {
    ::ioctl(fd_, PPRELEASE);
    ::close(fd_);
  }
}

Status PpdevLptPort::write_data(std::uint8_t value) {
  unsigned char data = value;
  if (::ioctl(fd_, PPWDATA, &data) != 0) {
    return fail(system_error("PPWDATA", name_, errno));
  }
  return ok();
}

// -------------------------------------------------------------------------------------- pty

Expected<std::unique_ptr<PtyLptPort>, DriverError> PtyLptPort::open(const std::string& path) {
  const std::string object = "lpt:pty:" + path;
  base::UniqueFd fd(::open(path.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC));
  if (!fd.valid()) {
    return fail(system_error("open", object, errno));
  }
  if (::isatty(fd.get()) == 1) {
    // A terminal's output processing would rewrite some byte values; D8 needs them verbatim.
    termios settings{};
    if (::tcgetattr(fd.get(), &settings) != 0) {
      return fail(system_error("tcgetattr", object, errno));
    }
    ::cfmakeraw(&settings);
    if (::tcsetattr(fd.get(), TCSANOW, &settings) != 0) {
      return fail(system_error("tcsetattr", object, errno));
    }
  }
  return std::unique_ptr<PtyLptPort>(new PtyLptPort(fd.release(), object));
}

PtyLptPort::~PtyLptPort() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
}

Status PtyLptPort::write_data(std::uint8_t value) {
  while (true) {
    const ssize_t written = ::write(fd_, &value, 1);
    if (written == 1) {
      return ok();
    }
    if (written < 0 && errno == EINTR) {
      continue;
    }
    return fail(system_error("write", name_, written < 0 ? errno : EIO));
  }
}

// ---------------------------------------------------------------------------------- factory

Expected<std::unique_ptr<LptPort>, DriverError> open_lpt_port(const Endpoint& endpoint) {
  const auto* lpt = std::get_if<LptEndpoint>(&endpoint);
  if (lpt == nullptr) {
    return fail(make_error(ErrorKind::invalid_argument, "open lpt port", format_endpoint(endpoint),
                           "not an lpt: endpoint"));
  }
  auto widen = [](auto opened) -> Expected<std::unique_ptr<LptPort>, DriverError> {
    if (!opened) {
      return fail(opened.error());
    }
    return std::unique_ptr<LptPort>(std::move(*opened));
  };
  switch (lpt->backend) {
    case LptBackend::ppdev: return widen(PpdevLptPort::open(lpt->target));
    case LptBackend::pty: return widen(PtyLptPort::open(lpt->target));
    case LptBackend::gpio: return widen(GpioLptPort::open(lpt->target));
  }
  return fail(make_error(ErrorKind::invalid_argument, "open lpt port", format_endpoint(endpoint)));
}

}  // namespace ldoem::driver
