// Shared by the ISO-TP tests (isotp_test.cpp: frame vectors, lengths, sequence numbers;
// isotp_flow_test.cpp: flow control, timeouts, STmin, random round trips): frames from either
// side, counting payloads, the configurations both use, and a sender joined to a receiver.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <vector>

#include "ldoem/protocol/isotp.hpp"

namespace ldoem::protocol::isotp_test {

inline constexpr std::uint32_t kRequestId = kIsoTpHostToDeviceId;
inline constexpr std::uint32_t kReplyId = kIsoTpDeviceToHostId;

inline CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  const std::vector<std::uint8_t> copy(bytes);
  const std::optional<CanFrame> made = make_can_frame(id, copy);
  EXPECT_TRUE(made.has_value());
  return made.value_or(CanFrame{});
}

// A frame from the host (request identifier), as the emulator's receiver sees it.
inline CanFrame host(std::initializer_list<std::uint8_t> bytes) { return frame(kRequestId, bytes); }
// A frame from the device (reply identifier).
inline CanFrame device(std::initializer_list<std::uint8_t> bytes) { return frame(kReplyId, bytes); }

inline Bytes counting_bytes(std::size_t length, std::uint8_t first = 0) {
  // push_back rather than indexing a sized vector: g++ 12 at -O3 misreads the latter as an
  // overflow (-Wstringop-overflow) once the length is a known constant.
  Bytes bytes;
  bytes.reserve(length);
  for (std::size_t i = 0; i < length; ++i) {
    bytes.push_back(static_cast<std::uint8_t>(first + i));
  }
  return bytes;
}

inline IsoTpReceiverConfig receiver_config(std::uint8_t block_size = 0, base::SimTime st_min = {}) {
  IsoTpReceiverConfig config;
  config.flow_control_id = kReplyId;
  config.block_size = block_size;
  config.st_min = st_min;
  return config;
}

inline IsoTpSenderConfig sender_config(bool pad_frames = false) {
  IsoTpSenderConfig config;
  config.data_id = kReplyId;
  config.pad_frames = pad_frames;
  return config;
}

// Starts `message` and takes the frames due at `now`.
inline std::vector<CanFrame> start_and_poll(IsoTpSender& sender, base::SimTime now, const Bytes& message) {
  EXPECT_TRUE(sender.start(now, message).has_value());
  return sender.poll(now).frames;
}

// ---------------------------------------------------------------------------------------------
// Sender and receiver joined without bus delay: frames reach the other side at the time they
// are sent, flow control goes straight back. The harness only moves time to the next deadline.
struct TimedFrame {
  base::SimTime at;
  CanFrame frame;
};

struct Transfer {
  std::vector<TimedFrame> data_frames;
  std::vector<TimedFrame> flow_control_frames;
  std::vector<Bytes> messages;
  IsoTpSender::State final_state = IsoTpSender::State::idle;
};

inline Transfer run_transfer(IsoTpSender& sender, IsoTpReceiver& receiver, const Bytes& message,
                             base::SimTime now = {}) {
  Transfer transfer;
  EXPECT_TRUE(sender.start(now, message).has_value());
  for (int rounds = 0; rounds < 100000 && sender.busy(); ++rounds) {
    IsoTpSendPoll polled = sender.poll(now);
    for (const CanFrame& data : polled.frames) {
      transfer.data_frames.push_back({now, data});
      IsoTpReceiveResult received = receiver.on_frame(now, data);
      if (received.message) {
        transfer.messages.push_back(*received.message);
      }
      if (received.flow_control) {
        transfer.flow_control_frames.push_back({now, *received.flow_control});
        sender.on_flow_control(now, *received.flow_control);
      }
    }
    const std::optional<base::SimTime> next = sender.deadline();
    if (next && *next > now) {
      now = *next;
    }
  }
  transfer.final_state = sender.state();
  return transfer;
}

}  // namespace ldoem::protocol::isotp_test
