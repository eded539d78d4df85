// Byte-level side doors for the framing cases, which must put bytes on the wire that no
// TelegramTransport would ever write (a bad TCP checksum, a bad serial CRC, a broken ISO-TP sequence):
//  - RawTcpSession: its own TCP connection with its own deframer (the suite closes its
//    TelegramTransport first, so a device that takes one client at a time still works);
//  - RawSerialWriter: a second write-only descriptor on the same tty; replies still arrive
//    through the TelegramTransport's reassembler;
//  - RawCanWriter: a CAN_RAW socket that writes frames on the request id; replies still arrive
//    through the TelegramTransport on the response id.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "ldoem/driver/endpoint.hpp"
#include "ldoem/driver/transport.hpp"
#include "ldoem/protocol/bytes.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace ldoem::conformance {

using driver::Deadline;
using protocol::ByteView;
using protocol::Bytes;

// Owns one descriptor; closes it on destruction.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd = -1) : fd_(fd) {}
  ~FileDescriptor();
  FileDescriptor(FileDescriptor&& other) noexcept : fd_(other.release()) {}
  FileDescriptor& operator=(FileDescriptor&& other) noexcept;
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }
  int release();

 private:
  int fd_;
};

// Errors are one line naming the operation and object ("connect tcp:127.0.0.1:49152: ...").
using RawError = std::string;

class RawTcpSession {
 public:
  static base::Expected<RawTcpSession, RawError> connect(const driver::TcpEndpoint& endpoint, Deadline deadline);
  base::Expected<std::monostate, RawError> write(ByteView bytes);
  // The next well-formed telegram payload; nullopt at the deadline. Frames with a bad checksum
  // are dropped by the deframer (spec 4.1: as S1 does).
  base::Expected<std::optional<Bytes>, RawError> receive(Deadline deadline);

 private:
  explicit RawTcpSession(FileDescriptor fd) : fd_(std::move(fd)) {}
  FileDescriptor fd_;
  protocol::TcpDeframer deframer_;
  std::deque<Bytes> received_;
};

class RawSerialWriter {
 public:
  static base::Expected<RawSerialWriter, RawError> open(const driver::SerialEndpoint& endpoint);
  base::Expected<std::monostate, RawError> write(ByteView bytes);

 private:
  explicit RawSerialWriter(FileDescriptor fd) : fd_(std::move(fd)) {}
  FileDescriptor fd_;
};

class RawCanWriter {
 public:
  static base::Expected<RawCanWriter, RawError> open(const driver::CanEndpoint& endpoint);
  // One classic CAN frame on the endpoint's request id, DLC = data size (<= 8).
  base::Expected<std::monostate, RawError> write_frame(ByteView data);

 private:
  RawCanWriter(FileDescriptor fd, std::uint32_t request_id) : fd_(std::move(fd)), request_id_(request_id) {}
  FileDescriptor fd_;
  std::uint32_t request_id_;
};

}  // namespace ldoem::conformance
