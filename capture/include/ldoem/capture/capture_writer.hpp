// Writes what crosses ldoem's wires into a pcapng file that Wireshark and tshark open
// (docs/capture.md). Every file holds four interfaces, one per transport:
//   0 "can"    LINKTYPE_CAN_SOCKETCAN  every CAN frame, ISO-TP flow control included
//   1 "tcp"    LINKTYPE_IPV4           synthesized IPv4/TCP: device 127.0.0.2:49152, host
//                                      127.0.0.1:(40000 + connection), a SYN handshake when a
//                                      connection first appears in a file, sequence numbers
//                                      counting the real bytes, segments of at most 1460 bytes,
//                                      FIN both ways at a close, RST from the device at a reset
//   2 "serial" LINKTYPE_USER0          direction byte + the bytes of the line
//   3 "lpt"    LINKTYPE_USER1          direction byte 0 + data-register values (D8)
// Timestamps are device time (D7) in nanoseconds. Each call writes its blocks with one write(2),
// so a crash loses at most the telegram being written; a failed write is cut back, so the file
// always ends at a block boundary. With a size cap the file rotates: FILE is always the newest,
// older ones are FILE.1, FILE.2, ... up to max_files in all (the renames run on a worker thread;
// FILE.rotating.N exist while they wait for it).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <variant>
#include <thread>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/can_frame.hpp"
#include "ldoem/capture/capture_packets.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::capture {

using protocol::ByteView;
using base::SimTime;
using protocol::WireDirection;

inline constexpr std::uint32_t kCaptureCanInterface = 0;
inline constexpr std::uint32_t kCaptureTcpInterface = 1;
inline constexpr std::uint32_t kCaptureSerialInterface = 2;
inline constexpr std::uint32_t kCaptureLptInterface = 3;
inline constexpr std::uint32_t kSynthesizedDeviceIp = 0x7F000002;  // 127.0.0.2
inline constexpr std::uint32_t kSynthesizedHostIp = 0x7F000001;    // 127.0.0.1
inline constexpr std::uint16_t kSynthesizedHostPortBase = 40000;
inline constexpr std::size_t kSynthesizedSegmentBytes = 1460;

struct CaptureWriterOptions {
  std::filesystem::path path;
  std::uint64_t max_file_bytes = 0;  // 0: no cap, one file that grows
  unsigned max_files = 10;           // with a cap: files kept, the current one included (>= 1)
  std::string application = "ldoem";
};

struct CaptureWriterCounters {
  std::uint64_t records = 0;  // calls that wrote something
  std::uint64_t bytes = 0;    // bytes written to the current file
  std::uint64_t rotations = 0;
  std::uint64_t write_errors = 0;  // records not written (the file was cut back to the one before)
};

// Nothing, or what went wrong ("write FILE: No space left on device").
using Written = base::Expected<std::monostate, std::string>;

class CaptureWriter {
 public:
  // Creates (truncates) the file and writes the section and interface blocks.
  [[nodiscard]] static base::Expected<std::unique_ptr<CaptureWriter>, std::string> open(CaptureWriterOptions options);
  ~CaptureWriter();
  CaptureWriter(const CaptureWriter&) = delete;
  CaptureWriter& operator=(const CaptureWriter&) = delete;

  // Each returns the error when the record was not written (Written).
  [[nodiscard]] Written write_can(base::SimTime time, const protocol::CanFrame& frame, WireDirection direction);
  [[nodiscard]] Written write_tcp(base::SimTime time, std::uint32_t connection, WireDirection direction, ByteView bytes);
  // The connection ended: an orderly close is a FIN both ways; a reset (the device dropped it:
  // a tcp_reset fault, a power cycle) is one RST from the device. A later write on the same
  // index starts a new connection with its own handshake.
  [[nodiscard]] Written close_tcp(base::SimTime time, std::uint32_t connection, bool reset = false);
  [[nodiscard]] Written write_serial(base::SimTime time, WireDirection direction, ByteView bytes);
  [[nodiscard]] Written write_lpt(base::SimTime time, ByteView values);

  // Waits until the last rotation's renames are done (FILE.1 ... in place); their error, if any.
  [[nodiscard]] Written wait_for_rotation() { return finish_shifting(); }

  const CaptureWriterCounters& counters() const { return counters_; }
  const std::filesystem::path& path() const { return options_.path; }

 private:
  struct TcpConnection {
    std::uint32_t host_next = 1;    // next sequence number host -> device
    std::uint32_t device_next = 1;  // next sequence number device -> host
    bool announced = false;         // handshake written in the current file
  };
  explicit CaptureWriter(CaptureWriterOptions options);
  Written start_file();
  Written rotate();
  Written shift_outcome();  // takes shift_error_; called with shift_mutex_ held
  Written finish_shifting();  // waits until no rotation's renames are pending; their error
  std::filesystem::path aside_name(std::uint64_t sequence) const;  // FILE.rotating.N
  void shift_files();             // the worker thread
  Written commit(const std::function<protocol::Bytes()>& build);
  Written write_all(const protocol::Bytes& blocks);
  TcpSegment segment(std::uint32_t connection, WireDirection direction, std::uint8_t flags,
                               const TcpConnection& state) const;
  void append_packet(protocol::Bytes& out, std::uint32_t interface, base::SimTime time, ByteView data,
                     WireDirection direction) const;

  CaptureWriterOptions options_;
  int fd_ = -1;
  CaptureWriterCounters counters_;
  std::map<std::uint32_t, TcpConnection> connections_;
  // Rotation's renames on a worker thread (issue 27 D4); everything below shift_mutex_ is
  // guarded by it, except shifter_ and next_rotation_ (the caller's thread only).
  std::thread shifter_;
  std::uint64_t next_rotation_ = 0;
  std::mutex shift_mutex_;
  std::condition_variable shift_wake_;  // work pending, or stopping
  std::condition_variable shift_done_;  // a batch finished
  std::vector<std::uint64_t> pending_;  // FILE.rotating.N waiting to become FILE.1, oldest first
  bool shifting_ = false;
  bool stopping_ = false;
  std::string shift_error_;
};

}  // namespace ldoem::capture
