#include "ldoem/capture/capture_writer.hpp"

#include "ldoem/base/regular_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <functional>
#include <system_error>
#include <utility>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/capture/pcapng.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace ldoem::capture {

using protocol::Bytes;

namespace {

PacketDirection packet_direction(WireDirection direction) {
  return direction == WireDirection::host_to_device ? PacketDirection::inbound : PacketDirection::outbound;
}

std::filesystem::path numbered(const std::filesystem::path& path, unsigned index) {
  return path.string() + "." + std::to_string(index);
}

std::string errno_text(const char* operation, const std::filesystem::path& path) {
  return std::string(operation) + " " + path.string() + ": " + std::strerror(errno);
}

}  // namespace

CaptureWriter::CaptureWriter(CaptureWriterOptions options) : options_(std::move(options)) {}

CaptureWriter::~CaptureWriter() {
  if (fd_ >= 0) ::close(fd_);
  if (shifter_.joinable()) {
    {
      std::lock_guard lock(shift_mutex_);
      stopping_ = true;  // the worker finishes what is pending first
      shift_wake_.notify_all();
    }
    shifter_.join();
  }
}

base::Expected<std::unique_ptr<CaptureWriter>, std::string> CaptureWriter::open(CaptureWriterOptions options) {
  if (options.path.empty()) return base::Unexpected(std::string("capture: no file name"));
  if (options.max_files == 0) return base::Unexpected(std::string("capture: max_files must be at least 1"));
  std::unique_ptr<CaptureWriter> writer(new CaptureWriter(std::move(options)));
  if (auto started = writer->start_file(); !started) return base::Unexpected(std::move(started.error()));
  return writer;
}

Written CaptureWriter::start_file() {
  // Issue 27 (D11): a FIFO or device is refused at once, never waited on or written into.
  auto opened = base::open_regular_file(options_.path, O_WRONLY | O_CREAT | O_TRUNC);
  if (!opened) return base::Unexpected(options_.path.string() + ": " + opened.error().text);
  fd_ = opened->release();
  counters_.bytes = 0;
  for (auto& [index, connection] : connections_) connection.announced = false;
  Bytes header = encode_pcapng_section_header(options_.application);
  const std::pair<LinkType, const char*> interfaces[] = {
      {LinkType::can_socketcan, "can"}, {LinkType::ipv4, "tcp"}, {LinkType::user0, "serial"}, {LinkType::user1, "lpt"}};
  for (const auto& [link_type, name] : interfaces) {
    const Bytes block = encode_pcapng_interface(link_type, name);
    header.insert(header.end(), block.begin(), block.end());
  }
  return write_all(header);
}

// Issue 27 D4: the caller's thread (the daemon's event loop) does O(1) work per rotation and
// never waits: it moves FILE aside as FILE.rotating.N and starts a new FILE. A worker thread
// then shifts the older files. It takes every rotation pending at once (M of them) and moves
// FILE.i to FILE.i+M (dropping those beyond max_files - 1), then puts the M pending files in
// FILE.1 ... FILE.M, newest first: at most max_files - 1 renames per batch however fast the
// rotations come, and the files never get out of order.
Written CaptureWriter::rotate() {
  ::close(fd_);
  fd_ = -1;
  std::error_code ignored;
  if (options_.max_files == 1) {
    std::filesystem::remove(options_.path, ignored);
  } else {
    const std::uint64_t sequence = next_rotation_++;
    std::error_code error;
    std::filesystem::rename(options_.path, aside_name(sequence), error);
    if (error) return base::Unexpected("rename " + options_.path.string() + ": " + error.message());
    std::lock_guard lock(shift_mutex_);
    pending_.push_back(sequence);
    if (!shifter_.joinable()) shifter_ = std::thread([this] { shift_files(); });
    shift_wake_.notify_all();
  }
  ++counters_.rotations;
  if (Written started = start_file(); !started) return started;
  std::lock_guard lock(shift_mutex_);
  return shift_outcome();
}

std::filesystem::path CaptureWriter::aside_name(std::uint64_t sequence) const {
  return options_.path.string() + ".rotating." + std::to_string(sequence);
}

void CaptureWriter::shift_files() {
  std::unique_lock lock(shift_mutex_);
  for (;;) {
    shift_wake_.wait(lock, [this] { return !pending_.empty() || stopping_; });
    if (pending_.empty()) return;  // stopping, nothing left
    const std::vector<std::uint64_t> batch = std::exchange(pending_, {});
    shifting_ = true;
    lock.unlock();
    const std::size_t kept = options_.max_files - 1;  // numbered files FILE.1 .. FILE.kept
    const std::size_t moved = batch.size();
    std::error_code ignored;
    std::string error;
    for (std::size_t index = kept; index >= 1 && index + moved > kept; --index) {
      std::filesystem::remove(numbered(options_.path, static_cast<unsigned>(index)), ignored);
    }
    for (std::size_t index = kept > moved ? kept - moved : 0; index >= 1; --index) {
      std::filesystem::rename(numbered(options_.path, static_cast<unsigned>(index)),
                              numbered(options_.path, static_cast<unsigned>(index + moved)), ignored);
    }
    for (std::size_t newest = 0; newest < moved; ++newest) {
      const std::filesystem::path aside = aside_name(batch[moved - 1 - newest]);
      if (newest + 1 > kept) {
        std::filesystem::remove(aside, ignored);
        continue;
      }
      std::error_code failed;
      std::filesystem::rename(aside, numbered(options_.path, static_cast<unsigned>(newest + 1)), failed);
      if (failed) error = "rename " + aside.string() + ": " + failed.message();
    }
    lock.lock();
    shifting_ = false;
    if (!error.empty()) shift_error_ = error;
    shift_done_.notify_all();
  }
}

Written CaptureWriter::finish_shifting() {
  std::unique_lock lock(shift_mutex_);
  shift_done_.wait(lock, [this] { return pending_.empty() && !shifting_; });
  return shift_outcome();
}

// The renames' error since the last call, if any, as a Written (and forgotten).
Written CaptureWriter::shift_outcome() {
  std::string error = std::exchange(shift_error_, std::string());
  if (error.empty()) return std::monostate{};
  return base::Unexpected(std::move(error));
}

Written CaptureWriter::commit(const std::function<Bytes()>& build) {
  Bytes blocks = build();
  // The cap: a record never makes a file exceed it, except a record too large for any file.
  // Rotation resets what a new file must repeat (TCP handshakes), so the record is rebuilt.
  if (options_.max_file_bytes > 0 && counters_.bytes > 0 &&
      counters_.bytes + blocks.size() > options_.max_file_bytes) {
    if (Written rotated = rotate(); !rotated) return rotated;
    blocks = build();
  }
  return write_all(blocks);
}

// Issue 27 D9: a record is written whole or not at all. On a write error (a full disk) the
// file is cut back to where the record began, so that it ends at a block boundary and stays
// readable; the error is counted and returned (the recording tap reports it once and stops).
Written CaptureWriter::write_all(const Bytes& blocks) {
  if (fd_ < 0) return base::Unexpected("write " + options_.path.string() + ": capture file is not open");
  std::size_t done = 0;
  while (done < blocks.size()) {
    const ssize_t written = ::write(fd_, blocks.data() + done, blocks.size() - done);
    if (written < 0) {
      if (errno == EINTR) continue;
      std::string error = errno_text("write", options_.path);
      ++counters_.write_errors;
      if (done > 0 && ::ftruncate(fd_, static_cast<off_t>(counters_.bytes)) != 0) {
        error += "; cutting it back to its last whole block: " + std::string(std::strerror(errno));
      }
      ::lseek(fd_, static_cast<off_t>(counters_.bytes), SEEK_SET);
      return base::Unexpected(std::move(error));
    }
    done += static_cast<std::size_t>(written);
  }
  counters_.bytes += blocks.size();
  return std::monostate{};
}

void CaptureWriter::append_packet(Bytes& out, std::uint32_t interface, base::SimTime time, ByteView data,
                                  WireDirection direction) const {
  const auto time_ns = static_cast<std::uint64_t>(std::max<std::int64_t>(0, time.count()));
  const Bytes block = encode_pcapng_packet(interface, time_ns, data, packet_direction(direction));
  out.insert(out.end(), block.begin(), block.end());
}

Written CaptureWriter::write_can(base::SimTime time, const protocol::CanFrame& frame, WireDirection direction) {
  ++counters_.records;
  return commit([&] {
    Bytes blocks;
    append_packet(blocks, kCaptureCanInterface, time, encode_socketcan_packet(frame), direction);
    return blocks;
  });
}

TcpSegment CaptureWriter::segment(std::uint32_t connection, WireDirection direction, std::uint8_t flags,
                                            const TcpConnection& state) const {
  TcpSegment segment;
  const auto host_port = static_cast<std::uint16_t>(kSynthesizedHostPortBase + connection % 20000);
  const bool to_device = direction == WireDirection::host_to_device;
  segment.source_ip = to_device ? kSynthesizedHostIp : kSynthesizedDeviceIp;
  segment.destination_ip = to_device ? kSynthesizedDeviceIp : kSynthesizedHostIp;
  segment.source_port = to_device ? host_port : base::kHostTcpPort;
  segment.destination_port = to_device ? base::kHostTcpPort : host_port;
  segment.sequence = to_device ? state.host_next : state.device_next;
  segment.acknowledgement = to_device ? state.device_next : state.host_next;
  segment.flags = flags;
  return segment;
}

Written CaptureWriter::write_tcp(base::SimTime time, std::uint32_t connection, WireDirection direction, ByteView bytes) {
  TcpConnection* state = nullptr;
  const auto build = [&] {
    state = &connections_[connection];
    Bytes blocks;
    if (!state->announced) {
      // SYN, SYN-ACK, ACK so that Wireshark sees the stream start and counts relative sequences.
      TcpConnection before = *state;
      before.host_next -= 1;
      before.device_next -= 1;
      auto syn = segment(connection, WireDirection::host_to_device, kTcpSyn, before);
      syn.acknowledgement = 0;
      append_packet(blocks, kCaptureTcpInterface, time, encode_ipv4_tcp_packet(syn),
                    WireDirection::host_to_device);
      auto syn_ack = segment(connection, WireDirection::device_to_host, kTcpSyn | kTcpAck, before);
      syn_ack.acknowledgement = state->host_next;
      append_packet(blocks, kCaptureTcpInterface, time, encode_ipv4_tcp_packet(syn_ack),
                    WireDirection::device_to_host);
      append_packet(blocks, kCaptureTcpInterface, time,
                    encode_ipv4_tcp_packet(
                        segment(connection, WireDirection::host_to_device, kTcpAck, *state)),
                    WireDirection::host_to_device);
    }
    TcpConnection next = *state;
    std::size_t offset = 0;
    do {
      const std::size_t size = std::min(kSynthesizedSegmentBytes, bytes.size() - offset);
      auto data = segment(connection, direction, kTcpAck | kTcpPsh, next);
      data.payload.assign(bytes.begin() + static_cast<std::ptrdiff_t>(offset),
                          bytes.begin() + static_cast<std::ptrdiff_t>(offset + size));
      append_packet(blocks, kCaptureTcpInterface, time, encode_ipv4_tcp_packet(data), direction);
      (direction == WireDirection::host_to_device ? next.host_next : next.device_next) +=
          static_cast<std::uint32_t>(size);
      offset += size;
    } while (offset < bytes.size());
    return blocks;
  };
  ++counters_.records;
  Written written = commit(build);
  if (written) {
    state->announced = true;
    (direction == WireDirection::host_to_device ? state->host_next : state->device_next) +=
        static_cast<std::uint32_t>(bytes.size());
  }
  return written;
}

Written CaptureWriter::close_tcp(base::SimTime time, std::uint32_t connection, bool reset) {
  const auto found = connections_.find(connection);
  if (found == connections_.end()) return std::monostate{};
  TcpConnection state = found->second;
  connections_.erase(found);
  if (!state.announced) return std::monostate{};
  const std::uint8_t fin = kTcpFin | kTcpAck;
  ++counters_.records;
  return commit([&] {
    Bytes blocks;
    if (reset) {
      append_packet(blocks, kCaptureTcpInterface, time,
                    encode_ipv4_tcp_packet(segment(connection, WireDirection::device_to_host,
                                                             kTcpRst | kTcpAck, state)),
                    WireDirection::device_to_host);
      return blocks;
    }
    append_packet(blocks, kCaptureTcpInterface, time,
                  encode_ipv4_tcp_packet(segment(connection, WireDirection::host_to_device, fin, state)),
                  WireDirection::host_to_device);
    TcpConnection after = state;
    after.host_next += 1;
    append_packet(blocks, kCaptureTcpInterface, time,
                  encode_ipv4_tcp_packet(segment(connection, WireDirection::device_to_host, fin, after)),
                  WireDirection::device_to_host);
    return blocks;
  });
}

Written CaptureWriter::write_serial(base::SimTime time, WireDirection direction, ByteView bytes) {
  ++counters_.records;
  return commit([&] {
    Bytes blocks;
    append_packet(blocks, kCaptureSerialInterface, time,
                  encode_serial_packet({direction, Bytes(bytes.begin(), bytes.end())}), direction);
    return blocks;
  });
}

Written CaptureWriter::write_lpt(base::SimTime time, ByteView values) {
  ++counters_.records;
  return commit([&] {
    Bytes blocks;
    append_packet(blocks, kCaptureLptInterface, time,
                  encode_lpt_packet({Bytes(values.begin(), values.end())}), WireDirection::host_to_device);
    return blocks;
  });
}

}  // namespace ldoem::capture
