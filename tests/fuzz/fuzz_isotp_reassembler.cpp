// libFuzzer target: IsoTpReceiver (D1) fed CAN frames and timer calls made from the input.
//
// Input: 5 configuration bytes (max message length, block size, STmin, padding), then records.
// Each record starts with a control byte: bits 0..1 choose the event (0, 1: a frame with a
// DLC 0..8; 2: on_timer; 3: a frame with any identifier and any DLC byte, even above 8), bits
// 2..7 advance simulated time by their square in milliseconds (so N_Cr = 1000 ms expires
// sometimes). A frame then takes a DLC byte and 8 data bytes; a short input reads as zeros.
//
// Checked: no crash or UB (ASan/UBSan), the documented invariants below, and that every
// message the receiver completes survives a sender -> receiver round trip unchanged.
#include <cstddef>
#include <cstdint>

#include "ldoem/protocol/isotp.hpp"

namespace {

using ldoem::protocol::Bytes;
using ldoem::protocol::CanFrame;
using ldoem::protocol::IsoTpReceiver;
using ldoem::protocol::IsoTpReceiverConfig;
using ldoem::protocol::IsoTpReceiveResult;
using ldoem::protocol::IsoTpSender;
using ldoem::protocol::IsoTpSenderConfig;
using ldoem::base::SimTime;

class InputReader {
 public:
  InputReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool empty() const { return offset_ >= size_; }
  std::uint8_t next() { return offset_ < size_ ? data_[offset_++] : 0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

void check(bool holds) {
  if (!holds) {
    __builtin_trap();
  }
}

IsoTpReceiverConfig read_config(InputReader& input) {
  IsoTpReceiverConfig config;
  const std::uint32_t low = input.next();
  const std::uint32_t high = input.next();
  config.max_message_bytes = 1 + ((high << 8) | low);  // 1..65536
  config.block_size = input.next();
  config.st_min = ldoem::protocol::decode_st_min(input.next());
  config.pad_frames = (input.next() & 1) != 0;
  return config;
}

CanFrame read_frame(InputReader& input, bool any_id_and_length) {
  CanFrame frame;
  frame.id = ldoem::protocol::kIsoTpHostToDeviceId;
  if (any_id_and_length) {
    const std::uint32_t id_high = input.next();
    const std::uint32_t id_low = input.next();
    frame.id = ((id_high << 8) | id_low) & ldoem::protocol::kCanStandardIdMask;
    frame.length = input.next();
  } else {
    frame.length = static_cast<std::uint8_t>(input.next() % 9);
  }
  for (std::uint8_t& byte : frame.data) {
    byte = input.next();
  }
  return frame;
}

// A completed message must come out of a fresh sender -> receiver pair byte for byte.
void check_round_trip(const Bytes& message, std::size_t max_message_bytes) {
  IsoTpSender sender(IsoTpSenderConfig{});
  IsoTpReceiverConfig config;
  config.max_message_bytes = max_message_bytes;
  IsoTpReceiver receiver(config);
  check(sender.start(SimTime::zero(), message).has_value());
  SimTime now = SimTime::zero();
  bool completed = false;
  while (sender.busy()) {
    for (const CanFrame& frame : sender.poll(now).frames) {
      IsoTpReceiveResult result = receiver.on_frame(now, frame);
      check(!result.error);
      if (result.flow_control) {
        sender.on_flow_control(now, *result.flow_control);
      }
      if (result.message) {
        check(*result.message == message);
        completed = true;
      }
    }
    if (const auto next = sender.deadline(); next && *next > now) {
      now = *next;
    }
  }
  check(completed);
}

void check_result(const IsoTpReceiver& receiver, const IsoTpReceiveResult& result) {
  if (result.message) {
    check(!result.message->empty());
    check(result.message->size() <= receiver.config().max_message_bytes);
  }
  if (result.flow_control) {
    const CanFrame& fc = *result.flow_control;
    check(fc.id == receiver.config().flow_control_id);
    check(fc.length == 3 || fc.length == 8);
    check(fc.data[0] == 0x30 || fc.data[0] == 0x32);  // continue to send or overflow only
  }
  const bool receiving = receiver.state() == IsoTpReceiver::State::receiving;
  check(receiver.deadline().has_value() == receiving);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  InputReader input(data, size);
  const IsoTpReceiverConfig config = read_config(input);
  IsoTpReceiver receiver(config);
  SimTime now = SimTime::zero();
  std::uint64_t errors_before = 0;
  while (!input.empty()) {
    const std::uint8_t control = input.next();
    const std::int64_t advance_ms = (control >> 2) * (control >> 2);
    now += std::chrono::milliseconds(advance_ms);
    const int event = control & 0x03;
    IsoTpReceiveResult result;
    if (event == 2) {
      result = receiver.on_timer(now);
    } else {
      result = receiver.on_frame(now, read_frame(input, event == 3));
    }
    check_result(receiver, result);
    // Every error is counted, and counters never go back.
    const std::uint64_t errors_now = receiver.counters().errors();
    check(errors_now >= errors_before);
    check(!result.error || errors_now > errors_before);
    errors_before = errors_now;
    if (result.message) {
      check_round_trip(*result.message, config.max_message_bytes);
    }
  }
  return 0;
}
