#include "ldoem/driver/transport.hpp"

#include "ldoem/driver/can_transport.hpp"
#include "ldoem/driver/serial_transport.hpp"
#include "ldoem/driver/tcp_transport.hpp"

namespace ldoem::driver {
namespace {

using TransportResult = Expected<std::unique_ptr<TelegramTransport>, DriverError>;

template <class Concrete>
TransportResult widen(Expected<std::unique_ptr<Concrete>, DriverError> opened) {
  if (!opened) {
    return fail(opened.error());
  }
  return std::unique_ptr<TelegramTransport>(std::move(*opened));
}

struct Opener {
  TransportResult operator()(const CanEndpoint& can) const {
    if (can.kernel_isotp) {
      return widen(KernelIsoTpTransport::open(can));
    }
    return widen(CanIsoTpTransport::open(can));
  }
  TransportResult operator()(const TcpEndpoint& tcp) const { return widen(TcpTransport::connect(tcp)); }
  TransportResult operator()(const SerialEndpoint& serial) const { return widen(SerialTransport::open(serial)); }
  TransportResult operator()(const LptEndpoint& lpt) const {
    return fail(make_error(ErrorKind::invalid_argument, "open transport", format_endpoint(Endpoint{lpt}),
                           "an lpt: endpoint is a stepper port, not a telegram transport"));
  }
};

}  // namespace

std::vector<Bytes> TelegramTransport::take_arrived(std::size_t) { return {}; }

// For the descriptor-based transports: receive() with a deadline already passed polls once
// without waiting.
std::vector<Bytes> take_arrived_now(TelegramTransport& transport, std::size_t limit) {
  std::vector<Bytes> arrived;
  const Deadline now = Clock::now();
  while (arrived.size() < limit) {
    auto telegram = transport.receive(now);
    if (!telegram) {
      break;
    }
    arrived.push_back(std::move(*telegram));
  }
  return arrived;
}

Expected<std::unique_ptr<TelegramTransport>, DriverError> open_transport(const Endpoint& endpoint) {
  return std::visit(Opener{}, endpoint);
}

}  // namespace ldoem::driver
