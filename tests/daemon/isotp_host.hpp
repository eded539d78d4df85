// A test host on CAN_RAW (vcan0) that speaks ISO-TP with the project's own machines (D1): the
// LD's channel with the identifiers swapped. It answers the LD's first frames with flow control.
#pragma once

#include <chrono>
#include <optional>
#include <vector>

#include "ldoem/endpoints/isotp_channel.hpp"
#include "ldoem/io/can_socket.hpp"
#include "ldoem/protocol/bytes.hpp"

namespace ldoem::daemon::test {

using endpoints::IsoTpChannel;
using endpoints::IsoTpChannelConfig;
using endpoints::IsoTpChannelOutput;
using endpoints::CanIdPair;
using base::SimTime;

class IsoTpHost {
 public:
  // `ids` as the LD sees them (request = host -> LD).
  explicit IsoTpHost(CanIdPair ids, std::string_view interface_name = "vcan0");

  bool is_open() const { return socket_.has_value(); }
  // Sends `request` and returns the next telegram from the LD, within `limit`.
  std::optional<protocol::Bytes> exchange(const protocol::Bytes& request,
                                          std::chrono::milliseconds limit = std::chrono::seconds(10));
  void send(const protocol::Bytes& request);
  std::optional<protocol::Bytes> next(std::chrono::milliseconds limit = std::chrono::seconds(10));
  // Reads (and answers flow control) for `span`, returning every telegram seen.
  std::vector<protocol::Bytes> drain(std::chrono::milliseconds span);

 private:
  SimTime elapsed() const { return std::chrono::steady_clock::now() - start_; }
  void transmit(const std::vector<protocol::CanFrame>& frames);
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  IsoTpChannel channel_;
  std::optional<io::CanRawSocket> socket_;
};

}  // namespace ldoem::daemon::test
