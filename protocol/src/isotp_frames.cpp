// ISO-TP pieces both directions share: PCI type, STmin encoding, flow-control frames (D1).
#include <algorithm>

#include "ldoem/protocol/isotp.hpp"

namespace ldoem::protocol {

namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

constexpr std::uint8_t kStMinMaxMilliseconds = 0x7F;
constexpr std::uint8_t kStMinFirstMicroCode = 0xF1;  // 100 us
constexpr std::uint8_t kStMinLastMicroCode = 0xF9;   // 900 us
constexpr base::SimTime kStMinMicroStep = microseconds(100);

}  // namespace

std::optional<IsoTpFrameType> isotp_frame_type(const CanFrame& frame) {
  if (frame.payload().empty()) {
    return std::nullopt;
  }
  switch (frame.data[0] >> 4) {
    case 0x0:
      return IsoTpFrameType::single_frame;
    case 0x1:
      return IsoTpFrameType::first_frame;
    case 0x2:
      return IsoTpFrameType::consecutive_frame;
    case 0x3:
      return IsoTpFrameType::flow_control;
    default:
      return std::nullopt;  // 4..F: not used by ISO-TP on classic CAN
  }
}

base::SimTime decode_st_min(std::uint8_t st_min_byte) {
  if (st_min_byte <= kStMinMaxMilliseconds) {
    return milliseconds(st_min_byte);
  }
  if (st_min_byte >= kStMinFirstMicroCode && st_min_byte <= kStMinLastMicroCode) {
    return kStMinMicroStep * (st_min_byte - 0xF0);
  }
  return kIsoTpMaxStMin;  // reserved values: the standard's longest separation
}

std::uint8_t encode_st_min(base::SimTime separation) {
  if (separation <= base::SimTime::zero()) {
    return 0;
  }
  if (separation <= kStMinMicroStep * 9) {
    // Round up to the next 100 us so the peer never sends faster than asked.
    const auto steps = (separation + kStMinMicroStep - base::SimTime(1)) / kStMinMicroStep;
    return static_cast<std::uint8_t>(0xF0 + steps);
  }
  const auto whole_ms = (separation + milliseconds(1) - base::SimTime(1)) / milliseconds(1);
  return static_cast<std::uint8_t>(std::min<std::int64_t>(whole_ms, kStMinMaxMilliseconds));
}

CanFrame make_flow_control_frame(std::uint32_t id, IsoTpFlowStatus status,
                                 std::uint8_t block_size, std::uint8_t st_min_byte,
                                 bool pad_frames) {
  CanFrame frame;
  frame.id = id;
  frame.data.fill(kIsoTpPaddingByte);
  frame.data[0] = static_cast<std::uint8_t>(0x30 | static_cast<std::uint8_t>(status));
  frame.data[1] = block_size;
  frame.data[2] = st_min_byte;
  frame.length = static_cast<std::uint8_t>(pad_frames ? kCanMaxDataBytes : kIsoTpFlowControlBytes);
  return frame;
}

std::string_view describe(IsoTpReceiveError error) {
  switch (error) {
    case IsoTpReceiveError::bad_sequence:
      return "iso-tp consecutive frame with a wrong sequence number";
    case IsoTpReceiveError::unexpected_frame:
      return "iso-tp frame unexpected in the current reception state";
    case IsoTpReceiveError::too_large:
      return "iso-tp first frame announces more than the maximum message length";
    case IsoTpReceiveError::timeout:
      return "iso-tp N_Cr timeout waiting for a consecutive frame";
    case IsoTpReceiveError::malformed:
      return "iso-tp frame with an impossible length or control byte";
  }
  return "iso-tp receive error";
}

std::string_view describe(IsoTpSendError error) {
  switch (error) {
    case IsoTpSendError::busy:
      return "iso-tp sender is still sending a message";
    case IsoTpSendError::empty_message:
      return "iso-tp cannot send an empty message";
    case IsoTpSendError::too_large:
      return "iso-tp message longer than 2^32 - 1 bytes";
    case IsoTpSendError::timeout:
      return "iso-tp N_Bs timeout waiting for flow control";
    case IsoTpSendError::overflow:
      return "iso-tp peer answered flow control overflow";
    case IsoTpSendError::invalid_flow_status:
      return "iso-tp flow control with a reserved flow status";
    case IsoTpSendError::too_many_waits:
      return "iso-tp receiver sent more flow-control WAITs in a row than N_WFTmax";
  }
  return "iso-tp send error";
}

}  // namespace ldoem::protocol
