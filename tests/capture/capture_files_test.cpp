// Issue 27: capture files that are not what they claim. The reader read a whole 900 MiB file
// before it reported a bad block at byte 11016; a FIFO named as a capture or as a recording hung
// open(). Now the reader goes block by block and both refuse anything but a regular file.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "ldoem/capture/capture_reader.hpp"
#include "ldoem/capture/capture_writer.hpp"
#include "ldoem/capture/pcapng.hpp"
#include "ldoem/test_support/bounded_call.hpp"
#include "ldoem/test_support/temp_dir.hpp"

namespace ldoem::capture {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using protocol::Bytes;

// A pcapng section with one IPv4 interface and `packets` packets of 100 bytes.
Bytes good_capture(std::size_t packets) {
  Bytes file = encode_pcapng_section_header("test");
  const Bytes interface = encode_pcapng_interface(LinkType::ipv4, "tcp");
  file.insert(file.end(), interface.begin(), interface.end());
  for (std::size_t i = 0; i < packets; ++i) {
    const Bytes packet = encode_pcapng_packet(0, i * 1000, Bytes(100, 0x45), PacketDirection::inbound);
    file.insert(file.end(), packet.begin(), packet.end());
  }
  return file;
}

TEST(CaptureFiles, ABadBlockIsReportedWithoutReadingTheRestOfTheFile) {
  test_support::TempDir dir;
  const fs::path path = dir.folder() / "big.pcapng";
  Bytes file = good_capture(80);
  const std::size_t bad_at = file.size();
  const Bytes bad_block{0x06, 0, 0, 0, 0x0D, 0, 0, 0};  // length 13: not a multiple of 4
  file.insert(file.end(), bad_block.begin(), bad_block.end());
  { std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size())); }
  fs::resize_file(path, std::uintmax_t{512} << 20);  // the rest: 512 MiB of zeros, sparse
  const std::size_t before = test_support::peak_rss_bytes();
  const auto read = read_capture_packets(path);
  const std::size_t grown = test_support::peak_rss_bytes() - before;
  ASSERT_FALSE(read.has_value());
  EXPECT_NE(read.error().find("block at byte " + std::to_string(bad_at) + ": "), std::string::npos) << read.error();
  EXPECT_LT(grown, std::size_t{64} << 20) << "peak RSS grew by " << (grown >> 20) << " MiB";
}

TEST(CaptureFiles, AGoodFileReadBlockByBlockGivesEveryPacket) {
  test_support::TempDir dir;
  const fs::path path = dir.folder() / "good.pcapng";
  const Bytes file = good_capture(500);
  { std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size())); }
  const auto read = read_capture_packets(path);
  ASSERT_TRUE(read.has_value()) << read.error();
  const auto decoded = decode_pcapng(file);
  ASSERT_TRUE(decoded.has_value());
  ASSERT_EQ(read->packets.size(), decoded->size());
  EXPECT_EQ(read->packets.back().time.count(), static_cast<std::int64_t>(decoded->back().time_ns));
}

TEST(CaptureFiles, AFifoOrAFolderIsNamedAtOnce) {
  test_support::TempDir dir;
  const fs::path fifo = dir.folder() / "x.pcapng";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto read = test_support::call_within(10s, [fifo] {
    auto packets = read_capture_packets(fifo);
    return packets ? std::string() : packets.error();
  });
  ASSERT_TRUE(read.has_value()) << "reading a FIFO did not return within 10 s";
  EXPECT_NE(read->find("is a FIFO"), std::string::npos) << *read;
  auto write = test_support::call_within(10s, [fifo] {
    auto writer = CaptureWriter::open({fifo});
    return writer ? std::string() : writer.error();
  });
  ASSERT_TRUE(write.has_value()) << "recording into a FIFO did not return within 10 s";
  EXPECT_NE(write->find("is a FIFO"), std::string::npos) << *write;
  const auto folder = read_capture_packets(dir.folder());
  ASSERT_FALSE(folder.has_value());
  EXPECT_NE(folder.error().find("is a directory"), std::string::npos) << folder.error();
}

}  // namespace
}  // namespace ldoem::capture
