// read_capture_*: a classic pcap as tcpdump writes it (read through libpcap), a candump log,
// and clear errors for files that are none of the formats.
#include <gtest/gtest.h>
#include <pcap/pcap.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include "ldoem/capture/capture_reader.hpp"
#include "ldoem/capture/candump_log.hpp"
#include "ldoem/protocol/isotp.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace ldoem::capture {
namespace {

namespace fs = std::filesystem;
using protocol::Bytes;

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("ldoem-reader-" + std::to_string(::getpid()) + "-" + name);
}

// What tcpdump -w on an Ethernet interface would hold for one segment to or from the device.
Bytes ethernet_frame(const TcpSegment& segment) {
  Bytes frame{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0x08, 0x00};
  const Bytes ip = encode_ipv4_tcp_packet(segment);
  frame.insert(frame.end(), ip.begin(), ip.end());
  return frame;
}

TEST(CaptureReader, ClassicPcapFromTcpdump_IsReadThroughLibpcap) {
  const fs::path path = temp_file("eth.pcap");
  {
    pcap_t* dead = pcap_open_dead_with_tstamp_precision(DLT_EN10MB, 65535, PCAP_TSTAMP_PRECISION_MICRO);
    pcap_dumper_t* dumper = pcap_dump_open(dead, path.c_str());
    ASSERT_NE(dumper, nullptr) << pcap_geterr(dead);
    const TcpSegment request{0xC0A8010B, 0xC0A8010A, 51000, 49152, 1000, 1, 0x18,
                                       protocol::encode_tcp_frame(Bytes{0x01, 0x02})};
    const TcpSegment reply{0xC0A8010A, 0xC0A8010B, 49152, 51000, 1, 1011, 0x18,
                                     protocol::encode_tcp_frame(Bytes{0x81, 0x02, 0, 0, 0, 3})};
    int second = 100;
    for (const auto* segment : {&request, &reply}) {
      const Bytes frame = ethernet_frame(*segment);
      pcap_pkthdr header{};
      header.ts.tv_sec = second++;
      header.ts.tv_usec = 250;
      header.caplen = header.len = static_cast<bpf_u_int32>(frame.size());
      pcap_dump(reinterpret_cast<u_char*>(dumper), &header, frame.data());
    }
    pcap_dump_close(dumper);
    pcap_close(dead);
  }
  const auto conversation = read_capture_conversation(path);
  fs::remove(path);
  ASSERT_TRUE(conversation.has_value()) << conversation.error();
  EXPECT_EQ(conversation->format, CaptureFormat::pcap);
  const auto& telegrams = conversation->conversation.telegrams;
  ASSERT_EQ(telegrams.size(), 2u);
  EXPECT_EQ(telegrams[0].payload, (Bytes{0x01, 0x02}));
  EXPECT_EQ(telegrams[0].time, std::chrono::seconds(100) + std::chrono::microseconds(250));
  EXPECT_EQ(telegrams[1].payload, (Bytes{0x81, 0x02, 0, 0, 0, 3}));
  EXPECT_EQ(telegrams[1].direction, protocol::WireDirection::device_to_host);
}

// A tcpdump capture of a device configured to TCP port 4000: one connection, so both of its
// ports carry frames; the host's SYN and its first request name the device's port.
fs::path write_port_4000_pcap(const std::string& name, bool with_syn) {
  const fs::path path = temp_file(name);
  pcap_t* dead = pcap_open_dead_with_tstamp_precision(DLT_EN10MB, 65535, PCAP_TSTAMP_PRECISION_MICRO);
  pcap_dumper_t* dumper = pcap_dump_open(dead, path.c_str());
  std::vector<TcpSegment> segments;
  if (with_syn) segments.push_back({0xC0A8010B, 0xC0A8010A, 51000, 4000, 999, 0, kTcpSyn, {}});
  segments.push_back({0xC0A8010B, 0xC0A8010A, 51000, 4000, 1000, 1, 0x18, protocol::encode_tcp_frame(Bytes{0x01, 0x02})});
  segments.push_back({0xC0A8010A, 0xC0A8010B, 4000, 51000, 1, 1011, 0x18,
                      protocol::encode_tcp_frame(Bytes{0x81, 0x02, 0, 0, 0, 3})});
  int second = 100;
  for (const auto& segment : segments) {
    const Bytes frame = ethernet_frame(segment);
    pcap_pkthdr header{};
    header.ts.tv_sec = second++;
    header.caplen = header.len = static_cast<bpf_u_int32>(frame.size());
    pcap_dump(reinterpret_cast<u_char*>(dumper), &header, frame.data());
  }
  pcap_dump_close(dumper);
  pcap_close(dead);
  return path;
}

TEST(CaptureReader, AnotherTcpPort_IsDetectedFromTheFrameHeaders) {
  for (const bool with_syn : {true, false}) {
    const fs::path path = write_port_4000_pcap("port4000.pcap", with_syn);
    const auto conversation = read_capture_conversation(path);
    fs::remove(path);
    ASSERT_TRUE(conversation.has_value()) << conversation.error();
    EXPECT_EQ(conversation->conversation.tcp_port, 4000) << "with SYN " << with_syn;
    EXPECT_TRUE(conversation->conversation.tcp_port_detected);
    const auto& telegrams = conversation->conversation.telegrams;
    ASSERT_EQ(telegrams.size(), 2u);
    EXPECT_EQ(telegrams[0].direction, protocol::WireDirection::host_to_device);
    EXPECT_EQ(telegrams[1].payload, (Bytes{0x81, 0x02, 0, 0, 0, 3}));
  }
}

TEST(CaptureReader, AGivenTcpPort_OverridesTheDetection) {
  const fs::path path = write_port_4000_pcap("port4000-given.pcap", true);
  const auto given = read_capture_conversation(path, ConversationConfig{.tcp_port = 49152});
  const auto right = read_capture_conversation(path, ConversationConfig{.tcp_port = 4000});
  fs::remove(path);
  ASSERT_TRUE(given.has_value() && right.has_value());
  EXPECT_FALSE(given->conversation.tcp_port_detected);
  EXPECT_TRUE(given->conversation.telegrams.empty());
  EXPECT_EQ(right->conversation.telegrams.size(), 2u);
}

TEST(CaptureReader, CandumpLog_GivesTheIsoTpTelegrams) {
  const fs::path path = temp_file("log.log");
  {
    std::ofstream out(path);
    out << format_candump_line(1'000'000'000, "vcan0", *protocol::make_can_frame(0x6C0, Bytes{0x02, 0x01, 0x02})) << "\n";
    out << format_candump_line(1'002'000'000, "vcan0",
                                         *protocol::make_can_frame(0x6C1, Bytes{0x06, 0x81, 0x02, 0, 0, 0, 1}))
        << "\n";
  }
  const auto conversation = read_capture_conversation(path);
  fs::remove(path);
  ASSERT_TRUE(conversation.has_value()) << conversation.error();
  EXPECT_EQ(conversation->format, CaptureFormat::candump);
  ASSERT_EQ(conversation->conversation.telegrams.size(), 2u);
  EXPECT_EQ(conversation->conversation.telegrams[1].payload, (Bytes{0x81, 0x02, 0, 0, 0, 1}));
  EXPECT_EQ(conversation->conversation.telegrams[1].time, std::chrono::milliseconds(1002));
}

TEST(CaptureReader, BadFiles_AreErrorsThatNameTheFile) {
  const fs::path garbage = temp_file("garbage.bin");
  { std::ofstream(garbage) << "this is not a capture\n"; }
  const auto not_capture = read_capture_packets(garbage);
  ASSERT_FALSE(not_capture.has_value());
  EXPECT_NE(not_capture.error().find(garbage.string()), std::string::npos) << not_capture.error();
  { std::ofstream(garbage) << "(1.0) vcan0 6C0#0102\n(1.1) vcan0 6C0#1\n"; }
  const auto bad_log = read_capture_packets(garbage);
  ASSERT_FALSE(bad_log.has_value());
  EXPECT_NE(bad_log.error().find(":2: "), std::string::npos) << bad_log.error();
  { std::ofstream(garbage, std::ios::binary) << std::string("\x0A\x0D\x0D\x0A\x1C\x00\x00\x00", 8); }
  const auto cut = read_capture_packets(garbage);
  ASSERT_FALSE(cut.has_value());
  EXPECT_NE(cut.error().find("block at byte 0"), std::string::npos) << cut.error();
  fs::remove(garbage);
  EXPECT_FALSE(read_capture_packets(temp_file("missing")).has_value());
}

}  // namespace
}  // namespace ldoem::capture
