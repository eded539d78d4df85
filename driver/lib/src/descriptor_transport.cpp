#include "ldoem/driver/descriptor_transport.hpp"

#include "stream_io.hpp"

namespace ldoem::driver {

DescriptorTransport::DescriptorTransport(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}

DescriptorTransport::~DescriptorTransport() { fd_.reset(); }

void DescriptorTransport::close() { fd_.reset(); }

Status DescriptorTransport::send_framed(ByteView framed, Deadline deadline, const detail::StreamKind& kind) {
  if (!fd_.valid()) {
    return fail(make_error(ErrorKind::connection_closed, "send", name_, "transport closed"));
  }
  auto written = detail::write_when_ready(fd_.get(), framed, deadline, kind, name_);
  if (written) {
    ++counters_.telegrams_sent;
  }
  return written;
}

TransportCounters DescriptorTransport::counters_with(std::uint64_t dropped_frames, std::uint64_t skipped_bytes) const {
  TransportCounters counters = counters_;
  counters.dropped_frames = dropped_frames;
  counters.skipped_bytes = skipped_bytes;
  return counters;
}

}  // namespace ldoem::driver
