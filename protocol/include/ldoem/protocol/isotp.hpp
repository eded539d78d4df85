// ISO 15765-2 (ISO-TP) segmentation as D1 uses it: normal addressing on classic CAN, one
// telegram = one ISO-TP message whose payload is exactly the TCP payload (service WORD first).
//
// Frame layouts (byte 0 high nibble = protocol control information, PCI):
//   single frame       0L dd..          L = 1..7 payload bytes
//   first frame        1H LL dd dd dd dd dd dd   12-bit length HLL = 8..4095
//                      10 00 LL LL LL LL dd dd   32-bit escape for lengths over 4095
//   consecutive frame  2N dd..          N = sequence number 1,2..15,0,1.. (first CF is 1)
//   flow control       3S BS ST         S: 0 continue to send, 1 wait, 2 overflow
//                                       BS: CFs per block (0 = no further FC), ST: STmin
// Frames go out unpadded (DLC = bytes used) unless padding with 0xCC is configured; frames in
// are accepted padded or not, and a flow-control frame may be 3 bytes long (D1).
//
// Both machines are pure: time is a SimTime passed in, frames are values handed back to the
// caller, and the caller routes frames by identifier (flow-control frames to the sender of the
// same direction pair, everything else to the receiver).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <variant>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/can_frame.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::protocol {

// D1 defaults. Both identifiers are configurable (command line, SET_CONFIG key 0x0002).
inline constexpr std::uint32_t kIsoTpHostToDeviceId = 0x6C0;
inline constexpr std::uint32_t kIsoTpDeviceToHostId = 0x6C1;
inline constexpr std::uint8_t kIsoTpPaddingByte = 0xCC;
inline constexpr base::SimTime kIsoTpDefaultTimeout = std::chrono::milliseconds(1000);  // N_Bs = N_Cr

// Our bound on a reassembled telegram. D3: ISO-TP has no protocol limit below 4 GiB, so this
// is memory protection only; a 0.125 deg profile is about 5.8 kB.
inline constexpr std::size_t kIsoTpDefaultMaxMessageBytes = 65536;

inline constexpr std::size_t kIsoTpMaxSingleFrameBytes = 7;
inline constexpr std::size_t kIsoTpMaxShortFirstFrameLength = 4095;  // 12-bit FF_DL
inline constexpr std::uint64_t kIsoTpMaxEscapedLength = 0xFFFFFFFF;  // 32-bit FF_DL
inline constexpr std::size_t kIsoTpConsecutiveFrameBytes = 7;
inline constexpr std::size_t kIsoTpFlowControlBytes = 3;

// STmin: 0x00..0x7F milliseconds, 0xF1..0xF9 100..900 microseconds; every other value is
// reserved and a sender treats it as the longest time, 127 ms (ISO 15765-2).
inline constexpr base::SimTime kIsoTpMaxStMin = std::chrono::milliseconds(127);

enum class IsoTpFrameType : std::uint8_t {
  single_frame = 0,
  first_frame = 1,
  consecutive_frame = 2,
  flow_control = 3,
};

enum class IsoTpFlowStatus : std::uint8_t {
  continue_to_send = 0,
  wait = 1,
  overflow = 2,
};

// The PCI type of a frame, or nothing for an empty frame or a PCI nibble ISO-TP does not use.
// Lets an endpoint route flow-control frames to its sender and the rest to its receiver.
std::optional<IsoTpFrameType> isotp_frame_type(const CanFrame& frame);

// Separation time of a received STmin byte (reserved values: 127 ms, see kIsoTpMaxStMin).
base::SimTime decode_st_min(std::uint8_t st_min_byte);

// The STmin byte for a wanted separation: the smallest encodable time not below `separation`,
// so a peer never sends faster than asked; above 127 ms it is 127 ms.
std::uint8_t encode_st_min(base::SimTime separation);

// A flow-control frame `3S BS ST`, 3 bytes long or padded to 8 with 0xCC.
CanFrame make_flow_control_frame(std::uint32_t id, IsoTpFlowStatus status,
                                 std::uint8_t block_size, std::uint8_t st_min_byte,
                                 bool pad_frames);

// ---------------------------------------------------------------------------------------------
// Receiver: reassembles SF / FF+CF.. into telegrams and answers FF with flow control.

// Why a partial telegram was dropped or a frame rejected (D1: counted, nothing is sent, except
// the overflow flow control that refuses a too large first frame).
enum class IsoTpReceiveError : std::uint8_t {
  bad_sequence,      // CF with the wrong sequence number
  unexpected_frame,  // CF with no reception running, or SF/FF interrupting a reception
  too_large,         // FF announces more than max_message_bytes (answered with FC overflow)
  timeout,           // N_Cr expired waiting for the next CF
  malformed,         // impossible PCI / length / DLC; ignored
};

std::string_view describe(IsoTpReceiveError error);

struct IsoTpReceiverConfig {
  std::uint32_t flow_control_id = kIsoTpDeviceToHostId;  // identifier of the FC frames we send
  std::size_t max_message_bytes = kIsoTpDefaultMaxMessageBytes;
  std::uint8_t block_size = 0;                   // our BS (D1: 0 unless configured)
  base::SimTime st_min = base::SimTime::zero();              // our STmin, rounded up to an encodable value
  base::SimTime n_cr_timeout = kIsoTpDefaultTimeout;   // D1
  bool pad_frames = false;                       // pad our FC frames to 8 bytes with 0xCC
};

// What one call did. Any combination can occur: an SF that interrupts a reception completes a
// message and reports unexpected_frame; a too large FF yields an overflow FC and too_large.
// `error` names the first error of the call; the counters count every one.
struct IsoTpReceiveResult {
  std::optional<Bytes> message;          // a complete telegram
  std::optional<CanFrame> flow_control;  // put this on the bus now
  std::optional<IsoTpReceiveError> error;

  bool nothing() const { return !message && !flow_control && !error; }
};

struct IsoTpReceiverCounters {
  std::uint64_t messages = 0;
  std::uint64_t bad_sequence = 0;
  std::uint64_t unexpected_frame = 0;
  std::uint64_t too_large = 0;
  std::uint64_t timeout = 0;
  std::uint64_t malformed = 0;

  std::uint64_t errors() const {
    return bad_sequence + unexpected_frame + too_large + timeout + malformed;
  }
};

class IsoTpReceiver {
 public:
  enum class State : std::uint8_t { idle, receiving };

  explicit IsoTpReceiver(IsoTpReceiverConfig config = {});

  // One frame from the bus at `now`. A flow-control frame is not the receiver's business and
  // is ignored (nothing()). A reception whose N_Cr has expired is dropped first (timeout), and
  // a CF that arrives too late for it is then ignored.
  [[nodiscard]] IsoTpReceiveResult on_frame(base::SimTime now, const CanFrame& frame);

  // Call at or after deadline(): drops the partial telegram with `timeout` when N_Cr expired.
  [[nodiscard]] IsoTpReceiveResult on_timer(base::SimTime now);

  // When N_Cr expires, while a reception runs.
  std::optional<base::SimTime> deadline() const;

  // Forget any partial telegram without counting it (DO_RESET, closing the endpoint).
  void reset();

  State state() const { return state_; }
  const IsoTpReceiverCounters& counters() const { return counters_; }
  const IsoTpReceiverConfig& config() const { return config_; }

 private:
  void on_frame_idle(base::SimTime now, IsoTpFrameType type, const CanFrame& frame,
                     IsoTpReceiveResult& result);
  void on_frame_receiving(base::SimTime now, IsoTpFrameType type, const CanFrame& frame,
                          IsoTpReceiveResult& result);
  void accept_single_frame(const CanFrame& frame, IsoTpReceiveResult& result);
  void accept_first_frame(base::SimTime now, const CanFrame& frame, IsoTpReceiveResult& result);
  void accept_consecutive_frame(base::SimTime now, const CanFrame& frame, IsoTpReceiveResult& result);
  void drop(IsoTpReceiveError error, IsoTpReceiveResult& result);
  void count(IsoTpReceiveError error, IsoTpReceiveResult& result);
  CanFrame flow_control(IsoTpFlowStatus status) const;

  IsoTpReceiverConfig config_;
  std::uint8_t st_min_byte_;
  State state_ = State::idle;
  Bytes buffer_;                      // never reserved beyond config_.max_message_bytes
  std::size_t expected_length_ = 0;   // FF_DL of the running reception
  std::uint8_t next_sequence_ = 0;
  std::uint8_t frames_left_in_block_ = 0;  // only meaningful with block_size > 0
  base::SimTime consecutive_frame_deadline_{};
  IsoTpReceiverCounters counters_;
};

// ---------------------------------------------------------------------------------------------
// Sender: segments one telegram and paces it by the peer's flow control.

enum class IsoTpSendError : std::uint8_t {
  busy,                 // start() while a message is still being sent
  empty_message,        // ISO-TP on classic CAN cannot carry 0 bytes (SF_DL 0 is reserved)
  too_large,            // more than 2^32 - 1 bytes
  timeout,              // N_Bs expired waiting for flow control
  overflow,             // the peer answered FC overflow
  invalid_flow_status,  // the peer's FC carried a reserved flow status
  too_many_waits,       // more FC WAITs in a row than N_WFTmax (max_wait_frames)
};

std::string_view describe(IsoTpSendError error);

// N_WFTmax default: ten WAITs in a row, 10 s at D1's N_Bs of 1 s if the peer sends each just in
// time; a receiver that needs longer is not one a host or the LD should wait on.
inline constexpr std::uint32_t kIsoTpDefaultMaxWaitFrames = 10;

struct IsoTpSenderConfig {
  std::uint32_t data_id = kIsoTpDeviceToHostId;  // identifier of SF/FF/CF frames
  bool pad_frames = false;                        // D1: unpadded unless configured
  base::SimTime n_bs_timeout = kIsoTpDefaultTimeout;    // D1
  // N_WFTmax (ISO 15765-2): FC WAITs accepted in a row before the message is given up
  // (IsoTpSendError::too_many_waits). Each WAIT restarts N_Bs, so without it a peer answering
  // WAIT forever held the sender forever (issue 11).
  std::uint32_t max_wait_frames = kIsoTpDefaultMaxWaitFrames;
};

struct IsoTpSendPoll {
  std::vector<CanFrame> frames;    // put these on the bus now, in order
  std::optional<base::SimTime> deadline; // call poll() again at this time (STmin or N_Bs)
};

class IsoTpSender {
 public:
  enum class State : std::uint8_t { idle, sending, waiting_for_flow_control, done, failed };

  explicit IsoTpSender(IsoTpSenderConfig config = {});

  // Takes a copy of `message`; the first frame is due at `now`. Refused while busy.
  [[nodiscard]] base::Expected<std::monostate, IsoTpSendError> start(base::SimTime now, ByteView message);

  // Frames due at `now`. With STmin > 0 at most one CF per call, so that the spacing counts
  // from the time the caller really sent the previous one. Also detects N_Bs expiry.
  [[nodiscard]] IsoTpSendPoll poll(base::SimTime now);

  // A flow-control frame from the peer. Ignored unless the sender waits for one, and when it
  // is shorter than 3 bytes or not an FC frame.
  void on_flow_control(base::SimTime now, const CanFrame& frame);

  // When poll() has work: the next CF's time, or N_Bs expiry while waiting for FC.
  std::optional<base::SimTime> deadline() const;

  // Abandon the message without an error (DO_RESET, closing the endpoint).
  void reset();

  State state() const { return state_; }
  bool busy() const;
  std::optional<IsoTpSendError> error() const { return error_; }
  const IsoTpSenderConfig& config() const { return config_; }

 private:
  void send_due_frames(base::SimTime now, std::vector<CanFrame>& out);
  CanFrame next_first_or_single_frame();
  CanFrame next_consecutive_frame();
  CanFrame finish_frame(CanFrame frame) const;
  void wait_for_flow_control(base::SimTime now);
  void fail(IsoTpSendError error);

  IsoTpSenderConfig config_;
  State state_ = State::idle;
  std::optional<IsoTpSendError> error_;
  Bytes message_;
  std::size_t next_offset_ = 0;      // 0: the SF or FF is still due
  std::uint8_t next_sequence_ = 1;
  base::SimTime next_frame_due_{};
  std::optional<base::SimTime> last_consecutive_sent_;
  std::uint32_t waits_in_a_row_ = 0;  // FC WAITs since the last CTS (N_WFTmax)
  std::uint8_t peer_block_size_ = 0;
  std::uint8_t frames_left_in_block_ = 0;
  base::SimTime peer_st_min_{};
  base::SimTime flow_control_deadline_{};
};

}  // namespace ldoem::protocol
