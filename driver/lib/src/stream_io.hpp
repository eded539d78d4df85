// The one receive loop and the one write loop of the descriptor-based transports (TCP, serial,
// kernel ISO-TP): wait with poll(2) until the deadline, retry EINTR/EAGAIN, and turn what the
// kernel says into DriverErrors. What differs between the transports is data (StreamKind), not
// another copy of the loop.
#pragma once

#include <sys/types.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "ldoem/driver/error.hpp"
#include "ldoem/driver/transport.hpp"
#include "ldoem/protocol/framing.hpp"

namespace ldoem::driver::detail {

struct StreamKind {
  ssize_t (*read_some)(int fd, void* buffer, std::size_t size);
  ssize_t (*write_some)(int fd, const void* data, std::size_t size);
  // What a read of 0 bytes means (a TCP peer that closed, a tty that hung up); empty: nothing,
  // the wait goes on (a datagram socket).
  const char* end_of_stream;
  // A pseudo terminal whose other side closed reads EIO: the same end as end_of_stream.
  bool eio_is_end_of_stream;
  // The timeout detail of a write that found no room before the deadline.
  const char* no_room;
};

// recv(2), and send(2) with MSG_NOSIGNAL: a peer that went away is an error return, never a
// SIGPIPE.
extern const StreamKind kTcpStream;
// read(2)/write(2) on a tty or pseudo terminal.
extern const StreamKind kSerialLine;
// read(2)/write(2) on a CAN_ISOTP socket: one telegram per call.
extern const StreamKind kIsoTpDatagrams;

// Waits until `fd` is readable or `deadline`, then reads at most buffer.size() bytes; returns how
// many (> 0). Errors: timeout, connection_closed (end of stream), system (errno kept in
// system_errno).
Expected<std::size_t, DriverError> read_when_ready(int fd, std::span<std::uint8_t> buffer, Deadline deadline,
                                                   const StreamKind& kind, const std::string& name);

// Writes all of `bytes`, waiting for room until `deadline`. Errors: timeout, system.
Status write_when_ready(int fd, ByteView bytes, Deadline deadline, const StreamKind& kind, const std::string& name);

// Reads until the deframer (protocol::TcpDeframer, protocol::SerialReplyReassembler) has given at
// least one telegram, queues all it gives, and returns the oldest. Frames the deframer rejects
// are dropped silently here (spec 4.1, 4.2); the deframer counts them. With a `frame_gap` (a
// deframer that can abandon_frame()), a frame that started but got no byte for that long is
// given up and its bytes searched again for the next frame, so a frame cut short on the wire
// does not swallow the reply that follows it.
template <std::size_t kChunkBytes, class Deframer>
Expected<Bytes, DriverError> receive_telegram(int fd, Deadline deadline, const StreamKind& kind,
                                              const std::string& name, Deframer& deframer,
                                              std::deque<Bytes>& received, TransportCounters& counters,
                                              std::optional<std::chrono::milliseconds> frame_gap = std::nullopt) {
  const auto take = [&received](std::vector<protocol::DeframerEvent> events) {
    for (auto& event : events) {
      if (auto* telegram = std::get_if<protocol::Telegram>(&event)) {
        received.push_back(std::move(telegram->payload));
      }
    }
  };
  Deadline last_byte = Clock::now();
  while (received.empty()) {
    if (fd < 0) {
      return fail(make_error(ErrorKind::connection_closed, "receive", name, "transport closed"));
    }
    Deadline wait_until = deadline;
    if constexpr (requires { deframer.abandon_frame(); }) {
      if (frame_gap && deframer.in_frame()) {
        wait_until = std::min(deadline, last_byte + *frame_gap);
      }
    }
    std::array<std::uint8_t, kChunkBytes> chunk{};
    const Expected<std::size_t, DriverError> count = read_when_ready(fd, chunk, wait_until, kind, name);
    if (!count) {
      if constexpr (requires { deframer.abandon_frame(); }) {
        if (count.error().kind == ErrorKind::timeout && wait_until < deadline) {
          take(deframer.abandon_frame());  // the gap passed inside a frame
          last_byte = Clock::now();
          continue;
        }
      }
      return fail(count.error());
    }
    last_byte = Clock::now();
    take(deframer.feed(ByteView(chunk.data(), *count)));
  }
  Bytes payload = std::move(received.front());
  received.pop_front();
  ++counters.telegrams_received;
  return payload;
}

}  // namespace ldoem::driver::detail
