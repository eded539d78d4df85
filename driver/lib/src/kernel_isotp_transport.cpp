// The kernel's ISO-TP socket (can-isotp, Linux >= 5.10) for hosts that have it: the same D1
// mapping as CanIsoTpTransport, segmentation done by the kernel.
#include <linux/can.h>
#include <linux/can/isotp.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <vector>

#include "fd_util.hpp"
#include "ldoem/driver/can_transport.hpp"

namespace ldoem::driver {
namespace {

// Largest telegram we read in one piece; D3 gives ISO-TP no protocol limit, this is memory
// protection only (as protocol::kIsoTpDefaultMaxMessageBytes).
constexpr std::size_t kMaxMessageBytes = protocol::kIsoTpDefaultMaxMessageBytes;

bool means_no_isotp(int errno_value) {
  return errno_value == EPROTONOSUPPORT || errno_value == EAFNOSUPPORT ||
         errno_value == ESOCKTNOSUPPORT || errno_value == EPROTOTYPE;
}

CanEndpoint user_space_twin(CanEndpoint endpoint) {
  endpoint.kernel_isotp = false;
  return endpoint;
}

Status set_options(int fd, const IsoTpOptions& options, const std::string& object) {
  can_isotp_options isotp{};
  if (options.pad_frames) {
    isotp.flags = CAN_ISOTP_TX_PADDING;
    isotp.txpad_content = protocol::kIsoTpPaddingByte;
  }
  if (::setsockopt(fd, SOL_CAN_ISOTP, CAN_ISOTP_OPTS, &isotp, sizeof isotp) != 0) {
    return fail(system_error("setsockopt CAN_ISOTP_OPTS", object, errno));
  }
  can_isotp_fc_options flow{};
  flow.bs = options.block_size;
  flow.stmin = protocol::encode_st_min(options.st_min);
  flow.wftmax = 0;
  if (::setsockopt(fd, SOL_CAN_ISOTP, CAN_ISOTP_RECV_FC, &flow, sizeof flow) != 0) {
    return fail(system_error("setsockopt CAN_ISOTP_RECV_FC", object, errno));
  }
  return ok();
}

}  // namespace

DriverError kernel_isotp_unavailable(const CanEndpoint& endpoint, int errno_value) {
  DriverError error = make_error(ErrorKind::unsupported, "socket CAN_ISOTP", format_endpoint(endpoint),
                                 "no CAN_ISOTP in this kernel; use " +
                                     format_endpoint(Endpoint{user_space_twin(endpoint)}) +
                                     " (user-space ISO-TP)");
  error.system_errno = errno_value;
  return error;
}

KernelIsoTpTransport::KernelIsoTpTransport(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}

KernelIsoTpTransport::~KernelIsoTpTransport() { close(); }

Expected<std::unique_ptr<KernelIsoTpTransport>, DriverError> KernelIsoTpTransport::open(
    const CanEndpoint& endpoint, IsoTpOptions options) {
  const std::string object = format_endpoint(endpoint);
  base::UniqueFd fd(::socket(PF_CAN, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_ISOTP));
  if (!fd.valid()) {
    if (means_no_isotp(errno)) {
      return fail(kernel_isotp_unavailable(endpoint, errno));
    }
    return fail(system_error("socket CAN_ISOTP", object, errno));
  }
  auto configured = set_options(fd.get(), options, object);
  if (!configured) {
    return fail(configured.error());
  }
  const unsigned index = ::if_nametoindex(endpoint.interface.c_str());
  if (index == 0) {
    return fail(system_error("if_nametoindex", object, errno));
  }
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  address.can_addr.tp.tx_id = endpoint.request_id;
  address.can_addr.tp.rx_id = endpoint.response_id;
  if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    return fail(system_error("bind", object, errno));
  }
  return std::unique_ptr<KernelIsoTpTransport>(new KernelIsoTpTransport(fd.release(), object));
}

Status KernelIsoTpTransport::send(ByteView payload, Deadline deadline) {
  if (fd_ < 0) {
    return fail(make_error(ErrorKind::connection_closed, "send", name_, "transport closed"));
  }
  while (true) {
    const ssize_t written = ::write(fd_, payload.data(), payload.size());
    if (written == static_cast<ssize_t>(payload.size())) {
      ++counters_.telegrams_sent;
      return ok();
    }
    if (written >= 0) {
      return fail(make_error(ErrorKind::system, "send", name_, "short ISO-TP write"));
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      return fail(system_error("send", name_, errno));
    }
    auto waited = detail::wait_for(fd_, POLLOUT, deadline, "send", name_);
    if (!waited) {
      return fail(waited.error());
    }
    if (*waited == detail::WaitOutcome::deadline_passed) {
      return fail(make_error(ErrorKind::timeout, "send", name_, "telegram not sent before the deadline"));
    }
  }
}

Expected<Bytes, DriverError> KernelIsoTpTransport::receive(Deadline deadline) {
  std::vector<std::uint8_t> buffer(kMaxMessageBytes);
  while (true) {
    if (fd_ < 0) {
      return fail(make_error(ErrorKind::connection_closed, "receive", name_, "transport closed"));
    }
    const ssize_t count = ::read(fd_, buffer.data(), buffer.size());
    if (count > 0) {
      ++counters_.telegrams_received;
      return Bytes(buffer.begin(), buffer.begin() + count);
    }
    if (count < 0 && errno != EINTR && errno != EAGAIN && errno != EWOULDBLOCK) {
      if (errno == EILSEQ || errno == EBADMSG || errno == ETIMEDOUT || errno == EPROTO) {
        ++counters_.dropped_frames;  // the kernel dropped a broken segment sequence (D1)
        continue;
      }
      return fail(system_error("receive", name_, errno));
    }
    auto waited = detail::wait_for(fd_, POLLIN, deadline, "receive", name_);
    if (!waited) {
      return fail(waited.error());
    }
    if (*waited == detail::WaitOutcome::deadline_passed) {
      return fail(make_error(ErrorKind::timeout, "receive", name_, "no telegram before the deadline"));
    }
  }
}

void KernelIsoTpTransport::close() {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

}  // namespace ldoem::driver
