// Writes the captures the dissector tests run tshark on (tests/wireshark/check_dissector.py):
//   vectors.pcapng   every frame of spec section 7 (tests/vectors/spec-section7.yaml) on TCP,
//                    its payload again over ISO-TP on CAN, the serial requests of 7.4 on the
//                    serial line and every reply payload as a serial reply;
//   profiles.pcapng  generated profiles of several formats and sizes on all three transports
//                    (TCP split over segments, ISO-TP with the 32-bit length escape, serial
//                    packages), then one frame with a bad checksum and one with a bad CRC;
//   profiles.json    what each profile telegram holds, from the encoder that wrote it.
// Usage: ldoem_dissector_fixtures VECTORS_YAML OUTDIR
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <iomanip>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "ldoem/capture/capture_writer.hpp"
#include "ldoem/protocol/isotp.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

using namespace ldoem;
using protocol::Bytes;
using protocol::WireDirection;

namespace {

Bytes parse_hex(const std::string& text) {
  Bytes out;
  std::istringstream in(text);
  std::string byte;
  while (in >> byte) out.push_back(static_cast<std::uint8_t>(std::stoul(byte, nullptr, 16)));
  return out;
}

void check(const std::string& error) {
  if (!error.empty()) {
    std::cerr << "ldoem_dissector_fixtures: " << error << "\n";
    std::exit(1);
  }
}

void check(const capture::Written& written) {
  if (!written) check(written.error());
}

// One telegram over ISO-TP as the bus carries it: the sender's frames and, for a multi-frame
// message, the receiver's flow control.
void write_isotp(capture::CaptureWriter& writer, base::SimTime& time, const Bytes& payload, WireDirection direction) {
  const bool to_device = direction == WireDirection::host_to_device;
  const std::uint32_t data_id = to_device ? protocol::kIsoTpHostToDeviceId : protocol::kIsoTpDeviceToHostId;
  const std::uint32_t fc_id = to_device ? protocol::kIsoTpDeviceToHostId : protocol::kIsoTpHostToDeviceId;
  protocol::IsoTpSender sender({.data_id = data_id});
  if (!sender.start(time, payload)) check("isotp start failed");
  protocol::IsoTpReceiver receiver({.flow_control_id = fc_id});
  for (int guard = 0; guard < 100000; ++guard) {
    const protocol::IsoTpSendPoll poll = sender.poll(time);
    for (const auto& frame : poll.frames) {
      check(writer.write_can(time, frame, direction));
      const auto result = receiver.on_frame(time, frame);
      if (result.flow_control) {
        const WireDirection back = to_device ? WireDirection::device_to_host : WireDirection::host_to_device;
        check(writer.write_can(time, *result.flow_control, back));
        sender.on_flow_control(time, *result.flow_control);
      }
      if (result.message) return;
    }
    time += std::chrono::microseconds(100);
  }
  check("isotp transfer did not finish");
}

struct Stamp {
  base::SimTime time{};
  base::SimTime next() { return time += std::chrono::milliseconds(1); }
};

protocol::Profile make_profile(std::uint16_t format, std::vector<std::size_t> points, std::uint16_t sent) {
  protocol::Profile profile;
  profile.format = format;
  profile.profile_sent = sent;
  profile.profile_count = static_cast<std::uint16_t>(100 + sent);
  profile.status.status = protocol::StatusByte{protocol::SensorMode::measure, protocol::MotorMode::ok};
  std::uint16_t start = 0;
  for (std::size_t s = 0; s < points.size(); ++s) {
    protocol::SectorBlock block;
    block.sector_num = static_cast<std::uint16_t>(2 * s);
    block.dir_step_ticks = 2;
    block.t_start_ms = static_cast<std::uint16_t>(1000 + s);
    block.start_dir_ticks = start;
    for (std::size_t p = 0; p < points[s]; ++p) {
      block.points.push_back({static_cast<std::uint16_t>(300 + 37 * (p + 11 * sent) % 5000), static_cast<std::uint16_t>(start + 2 * p),
                              static_cast<std::uint16_t>(p % 700)});
    }
    block.end_dir_ticks = static_cast<std::uint16_t>(start + 2 * (points[s] - 1));
    block.t_end_ms = static_cast<std::uint16_t>(block.t_start_ms + 50);
    start = static_cast<std::uint16_t>(block.end_dir_ticks + 200);
    profile.sectors.push_back(block);
  }
  return profile;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: ldoem_dissector_fixtures VECTORS_YAML OUTDIR\n";
    return 2;
  }
  const std::filesystem::path out = argv[2];
  std::filesystem::create_directories(out);
  const YAML::Node vectors = YAML::LoadFile(argv[1]);

  auto opened = capture::CaptureWriter::open({out / "vectors.pcapng"});
  if (!opened) check(opened.error());
  capture::CaptureWriter& writer = **opened;
  Stamp stamp;
  for (const char* table : {"tcp_requests", "tcp_replies"}) {
    const WireDirection direction = std::string(table) == "tcp_requests" ? WireDirection::host_to_device : WireDirection::device_to_host;
    for (const auto& row : vectors[table]) {
      check(writer.write_tcp(stamp.next(), 0, direction, parse_hex(row["frame"].as<std::string>())));
    }
  }
  for (const char* table : {"tcp_requests", "tcp_replies"}) {
    const WireDirection direction = std::string(table) == "tcp_requests" ? WireDirection::host_to_device : WireDirection::device_to_host;
    for (const auto& row : vectors[table]) {
      const Bytes frame = parse_hex(row["frame"].as<std::string>());
      const Bytes payload(frame.begin() + 8, frame.end() - 1);
      stamp.next();
      write_isotp(writer, stamp.time, payload, direction);
    }
  }
  for (const auto& row : vectors["serial_requests"]) {
    Bytes line{protocol::kSerialStx};
    for (char c : row["ascii"].as<std::string>()) line.push_back(static_cast<std::uint8_t>(c));
    line.push_back(protocol::kSerialEtx);
    check(writer.write_serial(stamp.next(), WireDirection::host_to_device, line));
  }
  for (const auto& row : vectors["tcp_replies"]) {
    const Bytes frame = parse_hex(row["frame"].as<std::string>());
    check(writer.write_serial(stamp.next(), WireDirection::device_to_host,
                              protocol::encode_serial_reply(protocol::ByteView(frame).subspan(8, frame.size() - 9))));
  }

  auto opened_profiles = capture::CaptureWriter::open({out / "profiles.pcapng"});
  if (!opened_profiles) check(opened_profiles.error());
  capture::CaptureWriter& profiles = **opened_profiles;
  struct Case {
    std::uint16_t format;
    std::vector<std::size_t> points;
  };
  // TCP and serial stay within D3's 5816 bytes; ISO-TP also gets one above 4095 (32-bit escape).
  const std::vector<Case> stream_cases = {{0x39FF, {2000}}, {0x3FFF, {300, 200}}, {0x0700, {100}}, {0x3DFF, {3, 0, 5}}};
  const std::vector<Case> can_cases = {{0x3DFF, {1441}}, {0x39FF, {10}}, {0x2120, {4, 6}}};
  std::ofstream json(out / "profiles.json");
  json << std::setprecision(17);
  json << "{\n";
  const auto emit = [&](const char* transport, const std::vector<Case>& cases, bool last) {
    json << "  \"" << transport << "\": [";
    std::uint16_t sent = 1;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const protocol::Profile profile = make_profile(cases[i].format, cases[i].points, sent++);
      const Bytes payload = protocol::encode_profile(profile);
      const Bytes request{0x03, 0x01, 0x00, 0x01, static_cast<std::uint8_t>(cases[i].format >> 8),
                          static_cast<std::uint8_t>(cases[i].format & 0xFF)};
      const std::string name = transport;
      if (name == "tcp") {
        check(profiles.write_tcp(stamp.next(), 0, WireDirection::host_to_device, protocol::encode_tcp_frame(request)));
        check(profiles.write_tcp(stamp.next(), 0, WireDirection::device_to_host, protocol::encode_tcp_frame(payload)));
      } else if (name == "serial") {
        check(profiles.write_serial(stamp.next(), WireDirection::host_to_device, protocol::encode_serial_request(request)));
        check(profiles.write_serial(stamp.next(), WireDirection::device_to_host, protocol::encode_serial_reply(payload)));
      } else {
        stamp.next();
        write_isotp(profiles, stamp.time, request, WireDirection::host_to_device);
        stamp.next();
        write_isotp(profiles, stamp.time, payload, WireDirection::device_to_host);
      }
      std::size_t total = 0;
      json << (i ? ", " : "") << "{\"format\": " << cases[i].format << ", \"bytes\": " << payload.size() << ", \"points\": [";
      for (std::size_t s = 0; s < cases[i].points.size(); ++s) {
        json << (s ? ", " : "") << cases[i].points[s];
        total += cases[i].points[s];
      }
      const bool has_distance = (cases[i].format & 0x0100) != 0 && total > 0;
      json << "], \"total\": " << total << ", \"first_distance_m\": "
           << (has_distance ? profile.sectors[0].points.empty() ? profile.sectors[1].points[0].distance_q8_m / 256.0
                                                               : profile.sectors[0].points[0].distance_q8_m / 256.0
                            : 0.0)
           << "}";
    }
    json << "]" << (last ? "\n" : ",\n");
  };
  emit("tcp", stream_cases, false);
  emit("serial", stream_cases, false);
  emit("can", can_cases, true);
  json << "}\n";
  // Damaged telegrams: the dissector must flag them (expert info), not crash or mis-decode.
  Bytes bad_checksum = protocol::encode_tcp_frame(Bytes{0x01, 0x02});
  bad_checksum.back() ^= 0x5A;
  check(profiles.write_tcp(stamp.next(), 1, WireDirection::host_to_device, bad_checksum));
  Bytes bad_crc = protocol::encode_serial_request(Bytes{0x01, 0x02});
  bad_crc[bad_crc.size() - 2] = bad_crc[bad_crc.size() - 2] == '0' ? '1' : '0';
  check(profiles.write_serial(stamp.next(), WireDirection::host_to_device, bad_crc));
  std::cout << "wrote " << (out / "vectors.pcapng").string() << " and " << (out / "profiles.pcapng").string() << "\n";
  return 0;
}
