// The kernel's ISO-TP socket (can-isotp, Linux >= 5.10) for hosts that have it: the same D1
// mapping as CanIsoTpTransport, segmentation done by the kernel.
#include <linux/can.h>
#include <linux/can/isotp.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <vector>

#include "stream_io.hpp"
#include "ldoem/driver/can_transport.hpp"

namespace ldoem::driver {
namespace {

// Largest telegram we read in one piece; D3 gives ISO-TP no protocol limit, this is memory
// protection only (as protocol::kIsoTpDefaultMaxMessageBytes).
constexpr std::size_t kMaxMessageBytes = protocol::kIsoTpDefaultMaxMessageBytes;

// The kernel's word for a segment sequence it dropped (wrong sequence number, N_Cr/N_Bs timeout).
bool means_broken_sequence(int errno_value) {
  return errno_value == EILSEQ || errno_value == EBADMSG || errno_value == ETIMEDOUT || errno_value == EPROTO;
}

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
  if (!fd_.valid()) {
    return fail(make_error(ErrorKind::connection_closed, "send", name_, "transport closed"));
  }
  // A CAN_ISOTP socket takes a telegram whole or not at all, so the write loop never splits one.
  auto written = detail::write_when_ready(fd_.get(), payload, deadline, detail::kIsoTpDatagrams, name_);
  if (written) {
    ++counters_.telegrams_sent;
  }
  return written;
}

Expected<Bytes, DriverError> KernelIsoTpTransport::receive(Deadline deadline) {
  std::vector<std::uint8_t> buffer(kMaxMessageBytes);
  while (true) {
    if (!fd_.valid()) {
      return fail(make_error(ErrorKind::connection_closed, "receive", name_, "transport closed"));
    }
    const Expected<std::size_t, DriverError> count =
        detail::read_when_ready(fd_.get(), buffer, deadline, detail::kIsoTpDatagrams, name_);
    if (count) {
      ++counters_.telegrams_received;
      return Bytes(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(*count));
    }
    if (count.error().kind == ErrorKind::system && means_broken_sequence(count.error().system_errno)) {
      ++counters_.dropped_frames;  // the kernel dropped a broken segment sequence (D1)
      continue;
    }
    return fail(count.error());
  }
}

void KernelIsoTpTransport::close() { fd_.reset(); }

}  // namespace ldoem::driver
