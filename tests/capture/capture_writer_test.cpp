// CaptureWriter: the four interfaces, TCP synthesis with a handshake and split segments, one
// flush per record, the size cap and rotation, and clear errors.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>
#include <vector>

#include "ldoem/capture/capture_reader.hpp"
#include "ldoem/capture/capture_writer.hpp"
#include "ldoem/capture/pcapng.hpp"
#include "ldoem/protocol/tcp_framing.hpp"
#include "ldoem/test_support/temp_dir.hpp"

namespace ldoem::capture {
namespace {

namespace fs = std::filesystem;
using protocol::Bytes;
using std::chrono::milliseconds;

using test_support::TempDir;

Bytes file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

Bytes profile_like_payload(std::size_t size) {
  Bytes payload{0x83, 0x01};
  for (std::size_t i = 2; i < size; ++i) payload.push_back(static_cast<std::uint8_t>(i * 7));
  return payload;
}

TEST(CaptureWriter, EveryRecord_IsOnDiskWhenTheCallReturns) {
  TempDir dir;
  auto writer = CaptureWriter::open({dir.folder() / "c.pcapng"});
  ASSERT_TRUE(writer.has_value()) << writer.error();
  const auto header_size = file_bytes(dir.folder() / "c.pcapng").size();
  EXPECT_GT(header_size, 0u);
  ASSERT_TRUE((*writer)->write_can(milliseconds(5), *protocol::make_can_frame(0x6C0, Bytes{0x02, 0x01, 0x02}),
                                 WireDirection::host_to_device));
  // No close, no destructor: the bytes are already in the file (a crash loses nothing written).
  const auto packets = decode_pcapng(file_bytes(dir.folder() / "c.pcapng"));
  ASSERT_TRUE(packets.has_value());
  ASSERT_EQ(packets->size(), 1u);
  EXPECT_EQ((*packets)[0].link_type, LinkType::can_socketcan);
  EXPECT_EQ((*packets)[0].time_ns, 5'000'000u);
  EXPECT_EQ((*packets)[0].direction, PacketDirection::inbound);
}

TEST(CaptureWriter, TcpTelegrams_AreSynthesizedSegmentsThatReassembleToTheSamePayloads) {
  TempDir dir;
  auto writer = CaptureWriter::open({dir.folder() / "t.pcapng"});
  ASSERT_TRUE(writer.has_value());
  const Bytes request{0x03, 0x01, 0x00, 0x00, 0x39, 0xFF};
  const Bytes reply = profile_like_payload(5000);  // four segments of at most 1460 bytes
  ASSERT_TRUE((*writer)->write_tcp(milliseconds(1), 0, WireDirection::host_to_device, protocol::encode_tcp_frame(request)));
  ASSERT_TRUE((*writer)->write_tcp(milliseconds(2), 0, WireDirection::device_to_host, protocol::encode_tcp_frame(reply)));
  ASSERT_TRUE((*writer)->write_tcp(milliseconds(3), 1, WireDirection::host_to_device, protocol::encode_tcp_frame(request)));
  ASSERT_TRUE((*writer)->close_tcp(milliseconds(4), 0));
  const auto packets = read_capture_packets(dir.folder() / "t.pcapng");
  ASSERT_TRUE(packets.has_value()) << packets.error();
  // Handshake (3) + request (1) + reply (4) + second connection's handshake (3) + request (1) + FIN (2).
  EXPECT_EQ(packets->packets.size(), 14u);
  for (const auto& packet : packets->packets) {
    const auto& segment = std::get<TcpSegment>(packet.payload);
    EXPECT_LE(segment.payload.size(), kSynthesizedSegmentBytes);
  }
  const auto conversation = read_capture_conversation(dir.folder() / "t.pcapng");
  ASSERT_TRUE(conversation.has_value());
  const auto& telegrams = conversation->conversation.telegrams;
  ASSERT_EQ(telegrams.size(), 3u);
  EXPECT_EQ(telegrams[0].payload, request);
  EXPECT_EQ(telegrams[1].payload, reply);
  EXPECT_EQ(telegrams[1].time, milliseconds(2));
  EXPECT_EQ(telegrams[2].stream, 1u);
  EXPECT_EQ(conversation->conversation.counters.framing_errors, 0u);
  EXPECT_EQ(conversation->conversation.counters.tcp_gaps, 0u);
}

TEST(CaptureWriter, CloseAndReset_EndAConnectionWithFinBothWaysOrOneRstFromTheDevice) {
  TempDir dir;
  auto writer = CaptureWriter::open({dir.folder() / "c.pcapng"});
  ASSERT_TRUE(writer.has_value());
  const Bytes frame = protocol::encode_tcp_frame(Bytes{0x01, 0x02});
  for (std::uint32_t connection : {0u, 1u}) {
    ASSERT_TRUE((*writer)->write_tcp(milliseconds(1), connection, WireDirection::host_to_device, frame));
  }
  ASSERT_TRUE((*writer)->close_tcp(milliseconds(2), 0));
  ASSERT_TRUE((*writer)->close_tcp(milliseconds(3), 1, true));
  const auto packets = read_capture_packets(dir.folder() / "c.pcapng");
  ASSERT_TRUE(packets.has_value()) << packets.error();
  std::vector<std::pair<std::uint16_t, std::uint8_t>> ends;  // (source port, flags) of FIN and RST
  for (const auto& packet : packets->packets) {
    const auto& segment = std::get<TcpSegment>(packet.payload);
    if ((segment.flags & (kTcpFin | kTcpRst)) != 0) ends.emplace_back(segment.source_port, segment.flags);
  }
  const std::uint8_t fin = kTcpFin | kTcpAck;
  const std::uint8_t rst = kTcpRst | kTcpAck;
  const std::uint16_t host0 = kSynthesizedHostPortBase;
  EXPECT_EQ(ends, (std::vector<std::pair<std::uint16_t, std::uint8_t>>{{host0, fin}, {49152, fin}, {49152, rst}}));
}

TEST(CaptureWriter, SizeCap_RotatesAndKeepsAtMostMaxFiles) {
  TempDir dir;
  auto writer = CaptureWriter::open({dir.folder() / "r.pcapng", 4096, 3});
  ASSERT_TRUE(writer.has_value());
  const Bytes frame = protocol::encode_tcp_frame(profile_like_payload(1000));
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE((*writer)->write_tcp(milliseconds(i), 0, WireDirection::device_to_host, frame));
  }
  EXPECT_GT((*writer)->counters().rotations, 2u);
  ASSERT_TRUE((*writer)->wait_for_rotation());  // the older files are renamed by a worker
  for (const auto& entry : fs::directory_iterator(dir.folder())) {
    EXPECT_EQ(entry.path().filename().string().find(".rotating"), std::string::npos) << entry.path();
  }
  EXPECT_TRUE(fs::exists(dir.folder() / "r.pcapng"));
  EXPECT_TRUE(fs::exists(dir.folder() / "r.pcapng.1"));
  EXPECT_TRUE(fs::exists(dir.folder() / "r.pcapng.2"));
  EXPECT_FALSE(fs::exists(dir.folder() / "r.pcapng.3"));
  for (const char* name : {"r.pcapng", "r.pcapng.1", "r.pcapng.2"}) {
    EXPECT_LE(fs::file_size(dir.folder() / name), 4096u) << name;
    // Each file stands alone: its own header, a handshake, and whole telegrams.
    const auto conversation = read_capture_conversation(dir.folder() / name);
    ASSERT_TRUE(conversation.has_value()) << name << ": " << conversation.error();
    EXPECT_FALSE(conversation->conversation.telegrams.empty()) << name;
    EXPECT_EQ(conversation->conversation.counters.tcp_gaps, 0u) << name;
  }
  // The newest file holds the newest record.
  const auto newest = read_capture_conversation(dir.folder() / "r.pcapng");
  EXPECT_EQ(newest->conversation.telegrams.back().time, milliseconds(19));
}

// Issue 27 D9: a disk that fills up (RLIMIT_FSIZE here: the write past it fails with EFBIG)
// leaves a file of whole blocks, readable without a warning; the error is counted.
TEST(CaptureWriter, WriteError_CutsTheFileBackToItsLastWholeBlock) {
  TempDir dir;
  auto writer = CaptureWriter::open({dir.folder() / "full.pcapng"});
  ASSERT_TRUE(writer.has_value());
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  const auto previous_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = before;
  small.rlim_cur = 10'001;  // not a block boundary
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  const Bytes frame = protocol::encode_tcp_frame(profile_like_payload(300));
  std::string error;
  for (int i = 0; i < 100 && error.empty(); ++i) {
    if (auto written = (*writer)->write_tcp(milliseconds(i), 0, WireDirection::device_to_host, frame); !written) {
      error = written.error();
    }
  }
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &before), 0);
  std::signal(SIGXFSZ, previous_handler);
  EXPECT_NE(error.find("File too large"), std::string::npos) << error;
  EXPECT_EQ((*writer)->counters().write_errors, 1u);
  EXPECT_EQ(fs::file_size(dir.folder() / "full.pcapng"), (*writer)->counters().bytes);
  const auto packets = read_capture_packets(dir.folder() / "full.pcapng");
  ASSERT_TRUE(packets.has_value()) << packets.error();
  EXPECT_EQ(packets->warning, "");
  EXPECT_FALSE(packets->packets.empty());
}

// A file that ends inside a block (cut by another writer or a crash): its whole blocks are read
// and a warning says where it was cut, as tshark does.
TEST(CaptureReader, FileCutInsideABlock_GivesItsWholeBlocksAndAWarning) {
  TempDir dir;
  {
    auto writer = CaptureWriter::open({dir.folder() / "cut.pcapng"});
    ASSERT_TRUE(writer.has_value());
    const Bytes frame = protocol::encode_tcp_frame(profile_like_payload(100));
    for (int i = 0; i < 3; ++i) ASSERT_TRUE((*writer)->write_tcp(milliseconds(i), 0, WireDirection::device_to_host, frame));
  }
  const auto whole = read_capture_packets(dir.folder() / "cut.pcapng");
  ASSERT_TRUE(whole.has_value());
  fs::resize_file(dir.folder() / "cut.pcapng", fs::file_size(dir.folder() / "cut.pcapng") - 5);
  const auto cut = read_capture_packets(dir.folder() / "cut.pcapng");
  ASSERT_TRUE(cut.has_value()) << cut.error();
  EXPECT_EQ(cut->packets.size(), whole->packets.size() - 1);
  EXPECT_NE(cut->warning.find("ends inside a block"), std::string::npos) << cut->warning;
}

TEST(CaptureWriter, SerialAndLpt_RoundTripWithDirection) {
  TempDir dir;
  auto writer = CaptureWriter::open({dir.folder() / "s.pcapng"});
  ASSERT_TRUE(writer.has_value());
  const Bytes line{0x02, 0x30, 0x03};
  ASSERT_TRUE((*writer)->write_serial(milliseconds(1), WireDirection::device_to_host, line));
  ASSERT_TRUE((*writer)->write_lpt(milliseconds(2), Bytes{0x02, 0x03}));
  const auto packets = read_capture_packets(dir.folder() / "s.pcapng");
  ASSERT_TRUE(packets.has_value());
  ASSERT_EQ(packets->packets.size(), 2u);
  EXPECT_EQ(std::get<SerialChunk>(packets->packets[0].payload),
            (SerialChunk{WireDirection::device_to_host, line}));
  EXPECT_EQ(std::get<LptWrites>(packets->packets[1].payload), (LptWrites{Bytes{0x02, 0x03}}));
}

TEST(CaptureWriter, UnwritablePath_IsAClearError) {
  const auto writer = CaptureWriter::open({"/nonexistent-dir/x.pcapng"});
  ASSERT_FALSE(writer.has_value());
  EXPECT_NE(writer.error().find("/nonexistent-dir/x.pcapng"), std::string::npos) << writer.error();
  EXPECT_NE(writer.error().find("No such file"), std::string::npos) << writer.error();
}

}  // namespace
}  // namespace ldoem::capture

#include "ldoem/capture/telegram_recorder.hpp"

namespace ldoem::capture {
namespace {

TEST(TelegramRecorder, EveryTransport_ReadsBackAsTheSameTelegrams) {
  TempDir dir;
  auto writer = CaptureWriter::open({dir.folder() / "rec.pcapng"});
  ASSERT_TRUE(writer.has_value());
  TelegramRecorder recorder(**writer);
  const Bytes request{0x03, 0x01, 0x00, 0x00, 0x3D, 0xFF};
  const Bytes long_reply = profile_like_payload(5000);  // ISO-TP with the 32-bit length escape
  using protocol::Transport;
  for (protocol::Transport transport : {protocol::Transport::tcp, protocol::Transport::serial, protocol::Transport::can}) {
    ASSERT_TRUE(recorder.record(milliseconds(1), transport, 0, WireDirection::host_to_device, request));
    ASSERT_TRUE(recorder.record(milliseconds(2), transport, 0, WireDirection::device_to_host, long_reply));
  }
  const auto conversation = read_capture_conversation(dir.folder() / "rec.pcapng");
  ASSERT_TRUE(conversation.has_value()) << conversation.error();
  const auto& telegrams = conversation->conversation.telegrams;
  ASSERT_EQ(telegrams.size(), 6u);
  for (std::size_t i = 0; i < 6; i += 2) {
    EXPECT_EQ(telegrams[i].payload, request) << i;
    EXPECT_EQ(telegrams[i + 1].payload, long_reply) << i;
    EXPECT_EQ(telegrams[i + 1].direction, WireDirection::device_to_host);
  }
  EXPECT_EQ(telegrams[4].transport, protocol::Transport::can);
  EXPECT_EQ(conversation->conversation.counters.framing_errors, 0u);
}

}  // namespace
}  // namespace ldoem::capture
