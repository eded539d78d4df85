#include "ldoem/driver/serial_transport.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <optional>
#include <variant>

#include "stream_io.hpp"

namespace ldoem::driver {
namespace {

constexpr std::size_t kSerialReadChunkBytes = 1024;

std::optional<speed_t> speed_constant(std::uint32_t baud) {
  switch (baud) {
    case 4800: return B4800;
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    default: return std::nullopt;
  }
}

// Spec 4.2: 8N1, no XON/XOFF; raw so that no byte is translated or swallowed.
Status configure_line(int fd, std::uint32_t baud, const std::string& object) {
  const auto speed = speed_constant(baud);
  if (!speed) {
    return fail(make_error(ErrorKind::invalid_argument, "configure", object,
                           "baud " + std::to_string(baud) + " is not in spec 3.4"));
  }
  termios settings{};
  if (::tcgetattr(fd, &settings) != 0) {
    return fail(system_error("tcgetattr", object, errno));
  }
  ::cfmakeraw(&settings);
  settings.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARENB | CSTOPB | CRTSCTS);
  settings.c_cflag |= CS8 | CLOCAL | CREAD;
  settings.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  settings.c_cc[VMIN] = 0;
  settings.c_cc[VTIME] = 0;
  if (::cfsetispeed(&settings, *speed) != 0 || ::cfsetospeed(&settings, *speed) != 0) {
    return fail(system_error("cfsetspeed", object, errno));
  }
  if (::tcsetattr(fd, TCSANOW, &settings) != 0) {
    return fail(system_error("tcsetattr", object, errno));
  }
  return ok();
}

}  // namespace

Expected<std::unique_ptr<SerialTransport>, DriverError> SerialTransport::open(const SerialEndpoint& endpoint) {
  const std::string object = format_endpoint(endpoint);
  base::UniqueFd fd(::open(endpoint.path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC));
  if (!fd.valid()) {
    return fail(system_error("open", object, errno));
  }
  auto configured = configure_line(fd.get(), endpoint.baud, object);
  if (!configured) {
    return fail(configured.error());
  }
  return std::unique_ptr<SerialTransport>(new SerialTransport(fd.release(), object));
}

Status SerialTransport::send(ByteView payload, Deadline deadline) {
  // The whole telegram in one buffer (D10); a tty may take it in several writes.
  return send_framed(protocol::encode_serial_request(payload), deadline, detail::kSerialLine);
}

Expected<Bytes, DriverError> SerialTransport::receive(Deadline deadline) {
  return detail::receive_telegram<kSerialReadChunkBytes>(fd_.get(), deadline, detail::kSerialLine, name_, reassembler_,
                                                   received_, counters_);
}

TransportCounters SerialTransport::counters() const {
  return counters_with(reassembler_.dropped_frames(), reassembler_.skipped_bytes());
}

}  // namespace ldoem::driver
