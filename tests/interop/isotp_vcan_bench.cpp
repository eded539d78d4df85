// ISO-TP through vcan0: N messages of M bytes from one CAN_RAW socket to another, segmented by
// protocol/'s IsoTpSender and reassembled by IsoTpReceiver (D1), the receiver's flow control
// routed back on the bus. Counts frames/s, messages/s and frames lost on the way.
//
// Runs inside User-Mode Linux (scripts/bench-isotp-vcan.sh). UML's vcan is a software loop on
// one emulated CPU: the two threads here (sender and receiver, like the daemon and a host) share
// that CPU, and a frame is "on the bus" when the kernel has queued it on the other socket. No
// bit rate applies (D1, D9 bus_timing is the daemon's business).
//
//   isotp_vcan_bench [--interface vcan0] [--messages 200] [--bytes 5800] [--block-size 0]
//                    [--st-min-us 0] [--receive-buffer BYTES] [--expect-all-delivered]
// Exit status: 0 ran (losses are reported, not an error, unless --expect-all-delivered);
// 1 socket failure or losses with --expect-all-delivered; 2 usage error.
#include <poll.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>

#include "ldoem/base/numbers.hpp"
#include "ldoem/protocol/isotp.hpp"
#include "raw_can_socket.hpp"

namespace {

using namespace std::chrono_literals;
using ldoem::interop::RawCanOptions;
using ldoem::interop::RawCanSocket;
using ldoem::protocol::Bytes;
using ldoem::protocol::CanFrame;
using ldoem::base::SimTime;
using Clock = std::chrono::steady_clock;

constexpr std::uint32_t kDataId = ldoem::protocol::kIsoTpDeviceToHostId;         // 0x6C1, as the LD
constexpr std::uint32_t kFlowControlId = ldoem::protocol::kIsoTpHostToDeviceId;  // 0x6C0, as the host

struct BenchOptions {
  std::string interface_name = "vcan0";
  std::size_t messages = 200;
  std::size_t message_bytes = 5800;  // a 0.125 deg profile, D1
  std::uint8_t block_size = 0;
  std::chrono::microseconds st_min{0};
  std::optional<int> receive_buffer_bytes;
  bool expect_all_delivered = false;
};

// The state machines take time as a value (STYLE): monotonic time since the process started.
SimTime now_sim() { return std::chrono::duration_cast<SimTime>(Clock::now().time_since_epoch()); }

template <class T>
bool parse_number(const char* text, T& out) {
  std::optional<T> value;
  if constexpr (std::is_floating_point_v<T>) {
    value = ldoem::base::parse_double(text);
  } else {
    value = ldoem::base::parse_integer<T>(text);
  }
  if (value) out = *value;
  return value.has_value();
}

std::optional<BenchOptions> parse_options(int argc, char** argv) {
  BenchOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string name = argv[i];
    const char* value = i + 1 < argc ? argv[i + 1] : nullptr;
    long number = 0;
    if (name == "--expect-all-delivered") { options.expect_all_delivered = true; continue; }
    if (value == nullptr) return std::nullopt;
    ++i;
    if (name == "--interface") { options.interface_name = value; continue; }
    if (!parse_number(value, number) || number < 0) return std::nullopt;
    if (name == "--messages") options.messages = static_cast<std::size_t>(number);
    else if (name == "--bytes" && number > 0) options.message_bytes = static_cast<std::size_t>(number);
    else if (name == "--block-size" && number <= 255) options.block_size = static_cast<std::uint8_t>(number);
    else if (name == "--st-min-us" && number <= 127000) options.st_min = std::chrono::microseconds(number);
    else if (name == "--receive-buffer" && number <= (1L << 30)) options.receive_buffer_bytes = static_cast<int>(number);
    else return std::nullopt;
  }
  return options;
}

// Message i: byte k is (7k + i) mod 256, so a reassembled message shows whether any byte moved.
Bytes message_bytes(std::size_t index, std::size_t size) {
  Bytes bytes(size);
  for (std::size_t k = 0; k < size; ++k) bytes[k] = static_cast<std::uint8_t>(7 * k + index);
  return bytes;
}

bool is_intact(const Bytes& message, std::size_t size) {
  if (message.size() != size) return false;
  for (std::size_t k = 1; k < size; ++k) {
    if (static_cast<std::uint8_t>(message[k] - message[k - 1]) != 7) return false;
  }
  return true;
}

// Waits until `fd` has `events` or `limit` passes.
void wait_for(int fd, short events, SimTime limit) {
  pollfd entry{fd, events, 0};
  const auto ms = std::chrono::ceil<std::chrono::milliseconds>(std::max(limit, SimTime::zero()));
  ::poll(&entry, 1, static_cast<int>(ms.count()));
}

// Writes, waiting for room while the socket's send queue is full. False on a socket error.
bool write_frame(RawCanSocket& socket, const CanFrame& frame, std::uint64_t& full_queue_waits) {
  for (;;) {
    auto written = socket.write(frame);
    if (!written) {
      std::fprintf(stderr, "%s\n", written.error().c_str());
      return false;
    }
    if (*written) return true;
    ++full_queue_waits;
    wait_for(socket.fd(), POLLOUT, 1ms);
  }
}

struct SenderResult {
  std::uint64_t data_frames = 0;
  std::uint64_t flow_controls_heard = 0;
  std::uint64_t failed_messages = 0;  // N_Bs timeout or overflow
  std::uint64_t full_queue_waits = 0;
  bool socket_failed = false;
};

void drain_flow_control(RawCanSocket& socket, ldoem::protocol::IsoTpSender& sender, SenderResult& result) {
  for (;;) {
    auto read = socket.read();
    if (!read || !read->frame) return;
    ++result.flow_controls_heard;
    sender.on_flow_control(now_sim(), *read->frame);
  }
}

// Sends one message to the end (done or failed).
bool send_message(RawCanSocket& socket, ldoem::protocol::IsoTpSender& sender, const Bytes& message,
                  SenderResult& result) {
  if (!sender.start(now_sim(), message)) return false;
  while (sender.busy()) {
    const auto polled = sender.poll(now_sim());
    for (const CanFrame& frame : polled.frames) {
      if (!write_frame(socket, frame, result.full_queue_waits)) return false;
      ++result.data_frames;
    }
    if (sender.state() == ldoem::protocol::IsoTpSender::State::waiting_for_flow_control) {
      wait_for(socket.fd(), POLLIN, polled.deadline.value_or(now_sim()) - now_sim());
    }
    drain_flow_control(socket, sender, result);
  }
  if (sender.state() == ldoem::protocol::IsoTpSender::State::failed) ++result.failed_messages;
  return true;
}

SenderResult run_sender(RawCanSocket& socket, const BenchOptions& options) {
  SenderResult result;
  ldoem::protocol::IsoTpSender sender(ldoem::protocol::IsoTpSenderConfig{kDataId, false, ldoem::protocol::kIsoTpDefaultTimeout});
  for (std::size_t i = 0; i < options.messages; ++i) {
    if (!send_message(socket, sender, message_bytes(i, options.message_bytes), result)) {
      result.socket_failed = true;
      break;
    }
  }
  return result;
}

struct ReceiverResult {
  std::uint64_t data_frames = 0;
  std::uint64_t flow_controls_sent = 0;
  std::uint64_t intact_messages = 0;
  std::uint64_t corrupt_messages = 0;
  std::uint64_t kernel_drops = 0;  // SO_RXQ_OVFL of the receiving socket
  std::uint64_t reassembly_errors = 0;
  std::uint64_t full_queue_waits = 0;
  Clock::time_point last_frame_at{};
  bool socket_failed = false;
};

void handle(ldoem::protocol::IsoTpReceiveResult received, RawCanSocket& socket, const BenchOptions& options,
            ReceiverResult& result) {
  if (received.flow_control) {
    if (!write_frame(socket, *received.flow_control, result.full_queue_waits)) result.socket_failed = true;
    ++result.flow_controls_sent;
  }
  if (received.message) {
    ++(is_intact(*received.message, options.message_bytes) ? result.intact_messages : result.corrupt_messages);
  }
}

// Feeds every frame waiting on the socket to the receiver; false on a socket error.
bool drain_frames(RawCanSocket& socket, ldoem::protocol::IsoTpReceiver& receiver, const BenchOptions& options,
                  ReceiverResult& result) {
  for (;;) {
    auto read = socket.read();
    if (!read) {
      std::fprintf(stderr, "%s\n", read.error().c_str());
      return false;
    }
    if (!read->frame) return !result.socket_failed;
    result.kernel_drops = read->kernel_drops;
    result.last_frame_at = Clock::now();
    ++result.data_frames;
    handle(receiver.on_frame(now_sim(), *read->frame), socket, options, result);
  }
}

// Reads until every message is in, or the sender is done and the bus has been quiet for 300 ms
// (everything in flight has arrived).
ReceiverResult run_receiver(RawCanSocket& socket, const BenchOptions& options, const std::atomic<bool>& sender_done) {
  ReceiverResult result;
  ldoem::protocol::IsoTpReceiverConfig config;
  config.flow_control_id = kFlowControlId;
  config.block_size = options.block_size;
  config.st_min = options.st_min;
  ldoem::protocol::IsoTpReceiver receiver(config);
  auto quiet_since = Clock::now();
  while (result.intact_messages + result.corrupt_messages < options.messages) {
    wait_for(socket.fd(), POLLIN, 20ms);
    const std::uint64_t frames_before = result.data_frames;
    if (!drain_frames(socket, receiver, options, result)) {
      result.socket_failed = true;
      break;
    }
    if (result.data_frames != frames_before) {
      quiet_since = Clock::now();
    } else if (receiver.deadline() && now_sim() >= *receiver.deadline()) {
      handle(receiver.on_timer(now_sim()), socket, options, result);
    } else if (sender_done && Clock::now() - quiet_since > 300ms) {
      break;
    }
  }
  result.reassembly_errors = receiver.counters().errors();
  return result;
}

std::optional<RawCanSocket> open_socket(const BenchOptions& options, std::uint32_t receive_id,
                                        std::optional<int> receive_buffer_bytes) {
  auto socket = RawCanSocket::open(options.interface_name,
                                   RawCanOptions{receive_id, true, receive_buffer_bytes});
  if (!socket) {
    std::fprintf(stderr, "%s\n", socket.error().c_str());
    return std::nullopt;
  }
  return std::move(*socket);
}

void report(const BenchOptions& options, int receive_buffer, const SenderResult& sent, const ReceiverResult& received,
            double seconds) {
  const double frames = static_cast<double>(received.data_frames + sent.flow_controls_heard);
  const std::uint64_t lost = sent.data_frames - std::min(sent.data_frames, received.data_frames);
  std::printf("messages %zu x %zu bytes, BS %u, STmin %lld us, receive buffer %d bytes (granted)\n",
              options.messages, options.message_bytes, static_cast<unsigned>(options.block_size),
              static_cast<long long>(options.st_min.count()), receive_buffer);
  std::printf("data frames sent %llu, received %llu, lost %llu (kernel drop counter %llu); flow controls %llu\n",
              static_cast<unsigned long long>(sent.data_frames), static_cast<unsigned long long>(received.data_frames),
              static_cast<unsigned long long>(lost), static_cast<unsigned long long>(received.kernel_drops),
              static_cast<unsigned long long>(received.flow_controls_sent));
  std::printf("messages intact %llu, corrupt %llu, sender failures %llu, reassembly errors %llu, full-queue waits %llu\n",
              static_cast<unsigned long long>(received.intact_messages),
              static_cast<unsigned long long>(received.corrupt_messages),
              static_cast<unsigned long long>(sent.failed_messages),
              static_cast<unsigned long long>(received.reassembly_errors),
              static_cast<unsigned long long>(sent.full_queue_waits + received.full_queue_waits));
  std::printf("RESULT bs=%u stmin_us=%lld rcvbuf=%d messages=%zu bytes=%zu seconds=%.3f frames_per_s=%.0f "
              "messages_per_s=%.1f payload_mb_per_s=%.2f sent_frames=%llu lost_frames=%llu kernel_drops=%llu "
              "intact=%llu failed=%llu\n",
              static_cast<unsigned>(options.block_size), static_cast<long long>(options.st_min.count()),
              receive_buffer, options.messages, options.message_bytes, seconds, frames / seconds,
              static_cast<double>(received.intact_messages) / seconds,
              static_cast<double>(received.intact_messages * options.message_bytes) / seconds / 1e6,
              static_cast<unsigned long long>(sent.data_frames), static_cast<unsigned long long>(lost),
              static_cast<unsigned long long>(received.kernel_drops),
              static_cast<unsigned long long>(received.intact_messages),
              static_cast<unsigned long long>(sent.failed_messages + received.corrupt_messages));
}

}  // namespace

int main(int argc, char** argv) {
  const auto options = parse_options(argc, argv);
  if (!options) {
    std::fprintf(stderr,
                 "usage: isotp_vcan_bench [--interface vcan0] [--messages 200] [--bytes 5800] [--block-size 0]\n"
                 "                        [--st-min-us 0] [--receive-buffer BYTES] [--expect-all-delivered]\n");
    return 2;
  }
  auto receiver_socket = open_socket(*options, kDataId, options->receive_buffer_bytes);
  auto sender_socket = open_socket(*options, kFlowControlId, std::nullopt);
  if (!receiver_socket || !sender_socket) return 1;

  std::atomic<bool> sender_done{false};
  ReceiverResult received;
  const auto start = Clock::now();
  std::thread receiver_thread([&] { received = run_receiver(*receiver_socket, *options, sender_done); });
  const SenderResult sent = run_sender(*sender_socket, *options);
  sender_done = true;
  receiver_thread.join();

  const double seconds = std::chrono::duration<double>(received.last_frame_at - start).count();
  report(*options, receiver_socket->receive_buffer_bytes(), sent, received, seconds > 0 ? seconds : 1e-9);
  if (sent.socket_failed || received.socket_failed) return 1;
  const bool all_delivered = received.intact_messages == options->messages;
  return options->expect_all_delivered && !all_delivered ? 1 : 0;
}
