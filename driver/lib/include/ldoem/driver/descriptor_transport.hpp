// What the TCP and the serial transport share: one descriptor, the endpoint's name, the
// telegrams that arrived and were not taken yet, the counters, and how a framed telegram goes out
// (whole, D10). They differ in how they open, how a telegram is framed, and how the bytes that
// come back are deframed.
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "ldoem/base/unique_fd.hpp"
#include "ldoem/driver/transport.hpp"

namespace ldoem::driver {

namespace detail {
struct StreamKind;
}

class DescriptorTransport : public TelegramTransport {
 public:
  ~DescriptorTransport() override;
  DescriptorTransport(const DescriptorTransport&) = delete;
  DescriptorTransport& operator=(const DescriptorTransport&) = delete;

  std::vector<Bytes> take_arrived(std::size_t limit) override { return take_arrived_now(*this, limit); }
  void close() override;
  const std::string& name() const override { return name_; }

 protected:
  DescriptorTransport(int fd, std::string name);

  // Writes `framed` (one whole telegram in its transport's framing) before `deadline`, in as
  // many writes as the line needs, and counts it. connection_closed after close().
  Status send_framed(ByteView framed, Deadline deadline, const detail::StreamKind& kind);
  // counters_ with what the deframer dropped and skipped.
  TransportCounters counters_with(std::uint64_t dropped_frames, std::uint64_t skipped_bytes) const;

  base::UniqueFd fd_;
  std::string name_;
  std::deque<Bytes> received_;
  TransportCounters counters_;
};

}  // namespace ldoem::driver
