// Writes the committed seed corpora of the protocol fuzz targets whose input is wire bytes
// (fuzz_message_decoder, fuzz_tcp_deframer, fuzz_serial_deframer, fuzz_isotp_reassembler):
//   ldoem_fuzz_seed_writer OUT_DIR     -> OUT_DIR/<target>/<seed>
// Every seed is made by the real encoders (requests and replies of spec 3, TCP and serial
// framing of spec 4, ISO-TP segmentation of D1), so the fuzzers start from telegrams a host or
// the LD really sends, plus the damaged variants that reach each decoder's error paths. The
// ctest fuzz/seeds_current checks that tests/fuzz/corpus holds exactly this output, so the seeds
// follow the encoders when they change. Regenerate with:
//   build/default/tests/fuzz/ldoem_fuzz_seed_writer tests/fuzz/corpus
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ldoem/protocol/isotp.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace {

namespace fs = std::filesystem;
using namespace ldoem::protocol;
using ldoem::base::SimTime;

class SeedDirectory {
 public:
  SeedDirectory(const fs::path& root, const std::string& target) : dir_(root / target) {
    fs::create_directories(dir_);
  }
  void write(const std::string& name, const Bytes& bytes) const {
    std::ofstream out(dir_ / name, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + (dir_ / name).string());
  }

 private:
  fs::path dir_;
};

Bytes join(std::initializer_list<Bytes> parts) {
  Bytes all;
  for (const Bytes& part : parts) all.insert(all.end(), part.begin(), part.end());
  return all;
}

// One revolution in the given format: `sectors` blocks of `points` points each.
Profile sample_profile(std::uint16_t format, std::size_t sectors, std::size_t points) {
  Profile profile;
  profile.format = format;
  profile.profile_sent = 1;
  profile.profile_count = 42;
  profile.status = make_status_block(SensorMode::measure, MotorMode::ok);
  for (std::size_t s = 0; s < sectors; ++s) {
    SectorBlock block;
    block.sector_num = static_cast<std::uint16_t>(s);
    block.dir_step_ticks = 8;
    block.t_start_ms = static_cast<std::uint16_t>(1000 + 10 * s);
    block.start_dir_ticks = static_cast<std::uint16_t>(720 * s);
    for (std::size_t p = 0; p < points; ++p) {
      block.points.push_back(ProfilePoint{static_cast<std::uint16_t>(256 * 3 + 7 * p),
                                          static_cast<std::uint16_t>(block.start_dir_ticks + 8 * p),
                                          static_cast<std::uint16_t>(100 + p)});
    }
    block.t_end_ms = static_cast<std::uint16_t>(block.t_start_ms + 5);
    block.end_dir_ticks = static_cast<std::uint16_t>(block.start_dir_ticks + 8 * (points - 1));
    profile.sectors.push_back(block);
  }
  return profile;
}

Bytes request(const Request& r) { return encode_request(r); }
Bytes response(const Response& r) { return encode_response(r); }

void write_message_decoder(const fs::path& root) {
  const SeedDirectory dir(root, "fuzz_message_decoder");
  const StatusBlock rotating = make_status_block(SensorMode::rotate, MotorMode::ok);
  dir.write("get_identification", request(GetIdentification{ident_item::kFirmwareVersion}));
  dir.write("get_status_s2_trailing_word", request(GetStatus{true}));
  dir.write("set_config_global", request(SetConfig{GlobalConfig{1, 10, 4, true}}));
  dir.write("set_config_can", request(SetConfig{CanConfig{}}));
  dir.write("get_config_ethernet", request(GetConfig{static_cast<std::uint16_t>(ConfigKey::ethernet)}));
  dir.write("set_function", request(SetFunction{1, sector_function::kNormalMeasurement, 2880, 0}));
  dir.write("get_profile_echo", request(GetProfile{0, kFormatRangeEcho}));
  dir.write("trans_rotate", request(TransRotate{10}));
  dir.write("do_reset", request(DoReset{reset_level::kRestart}));
  dir.write("reply_identification", response(IdentificationReply{"LD-OEM1000 V2.10"}));
  dir.write("reply_get_status", response(GetStatusReply{rotating, {}}));
  dir.write("reply_get_config_global", response(GetConfigReply{GlobalConfig{}}));
  dir.write("reply_get_function", response(GetFunctionReply{1, sector_function::kNormalMeasurement, 2880}));
  dir.write("reply_trans_measure", response(TransMeasureReply{rotating, measure_return::kSectorBordersNotConfigured}));
  dir.write("reply_service_failure", response(ServiceFailure{0x0011, FailureReason::wrong_length}));
  dir.write("profile_range_2_sectors", encode_profile(sample_profile(kFormatRange, 2, 5)));
  dir.write("profile_all_fields", encode_profile(sample_profile(profile_bits::kAllFields, 1, 4)));
}

// fuzz_tcp_deframer: the input is the stream; bit 0 of its first byte picks a 16-byte maximum,
// bit 1 the driver's resync. A frame starts with STX (0x02): full maximum, rescan_dropped.
void write_tcp_deframer(const fs::path& root) {
  const SeedDirectory dir(root, "fuzz_tcp_deframer");
  const Bytes status = encode_tcp_frame(request(GetStatus{}));
  const Bytes profile = encode_tcp_frame(encode_profile(sample_profile(kFormatRangeEcho, 1, 6)));
  Bytes bad_checksum = status;
  bad_checksum.back() ^= 0xFF;
  const Bytes truncated(profile.begin(), profile.begin() + 12);
  dir.write("one_request", status);
  dir.write("request_and_profile", join({status, profile}));
  dir.write("bad_checksum_then_request", join({bad_checksum, status}));
  dir.write("truncated_frame_then_request", join({truncated, status}));
  // A leading byte with bits 0 and 1 clear: the emulator's resync (after_error).
  dir.write("after_error_garbage_then_request", join({Bytes{0x00, 'U', 'S', 'P'}, status}));
  // Bit 0 set: a 16-byte maximum, so the profile is too_large.
  dir.write("small_maximum_profile", join({Bytes{0x01}, profile, status}));
}

// fuzz_serial_deframer: byte 0 chooses the chunk size (1 + b % 7) and, with bit 7, an 8-byte
// maximum; the rest goes to both the host-telegram deframer and the reply reassembler.
void write_serial_deframer(const fs::path& root) {
  const SeedDirectory dir(root, "fuzz_serial_deframer");
  const Bytes status = encode_serial_request(request(GetStatus{}));
  const Bytes set_function = encode_serial_request(request(SetFunction{0, sector_function::kNormalMeasurement, 5760, 1}));
  // More than 123 payload WORDs: the reply comes in two packages.
  const Bytes profile_reply = encode_serial_reply(encode_profile(sample_profile(kFormatRange, 1, 130)));
  const Bytes ident_reply = encode_serial_reply(response(IdentificationReply{"LD-OEM"}));
  Bytes bad_crc = status;
  bad_crc[bad_crc.size() - 2] = bad_crc[bad_crc.size() - 2] == '0' ? '1' : '0';
  Bytes bad_hex = set_function;
  bad_hex[6] = 'x';
  dir.write("request", join({Bytes{0x03}, status}));
  dir.write("two_requests_bytewise", join({Bytes{0x00}, status, set_function}));
  dir.write("reply_two_packages", join({Bytes{0x04}, profile_reply}));
  dir.write("reply_odd_identification", join({Bytes{0x01}, ident_reply}));
  dir.write("bad_crc_then_request", join({Bytes{0x02}, bad_crc, status}));
  dir.write("bad_hex_then_request", join({Bytes{0x05}, bad_hex, status}));
  dir.write("small_maximum", join({Bytes{0x86}, set_function, status}));
}

// fuzz_isotp_reassembler records: 5 configuration bytes (max length - 1 low/high, block size,
// STmin, padding), then per event a control byte (bits 0..1: 0 = frame on 0x6C0, 2 = timer;
// bits 2..7: sqrt of the milliseconds to advance) and, for a frame, its DLC and 8 data bytes.
class IsoTpRecording {
 public:
  IsoTpRecording(std::uint16_t max_minus_one, std::uint8_t block_size, bool pad)
      : bytes_{static_cast<std::uint8_t>(max_minus_one & 0xFF), static_cast<std::uint8_t>(max_minus_one >> 8),
               block_size, 0x00, static_cast<std::uint8_t>(pad ? 1 : 0)} {}

  void frame(const CanFrame& frame, std::uint8_t control = 0x00) {
    bytes_.push_back(control);
    bytes_.push_back(frame.length);
    bytes_.insert(bytes_.end(), frame.data.begin(), frame.data.end());
  }
  void timer(std::uint8_t sqrt_ms) { bytes_.push_back(static_cast<std::uint8_t>((sqrt_ms << 2) | 2)); }

  // The frames a sender makes for `message`, paced by a receiver configured as the recording
  // is (so a block size gets its flow control frames); `keep` limits how many are recorded.
  void message(const Bytes& message, bool pad, std::size_t keep = SIZE_MAX) {
    IsoTpSenderConfig sender_config;
    sender_config.data_id = kIsoTpHostToDeviceId;
    sender_config.pad_frames = pad;
    IsoTpSender sender(sender_config);
    IsoTpReceiverConfig receiver_config;
    receiver_config.max_message_bytes = 1 + (bytes_[0] | (bytes_[1] << 8));
    receiver_config.block_size = bytes_[2];
    IsoTpReceiver receiver(receiver_config);
    SimTime now = SimTime::zero();
    if (!sender.start(now, message)) throw std::runtime_error("ISO-TP sender refused a seed message");
    std::size_t recorded = 0;
    while (sender.busy() && recorded < keep) {
      for (const CanFrame& frame : sender.poll(now).frames) {
        if (recorded == keep) break;
        ++recorded;
        this->frame(frame);
        const IsoTpReceiveResult result = receiver.on_frame(now, frame);
        if (result.flow_control) sender.on_flow_control(now, *result.flow_control);
      }
      if (const auto next = sender.deadline(); next && *next > now) now = *next;
    }
  }
  const Bytes& bytes() const { return bytes_; }

 private:
  Bytes bytes_;
};

void write_isotp_reassembler(const fs::path& root) {
  const SeedDirectory dir(root, "fuzz_isotp_reassembler");
  const Bytes status = request(GetStatus{});
  const Bytes set_config = request(SetConfig{CanConfig{4, 0x6C0, 0x6C1, 2, 1}});
  const Bytes profile = encode_profile(sample_profile(kFormatRangeEcho, 2, 8));
  {
    IsoTpRecording rec(0xFFFF, 0, false);
    rec.message(status, false);
    rec.message(set_config, false);
    dir.write("single_frames", rec.bytes());
  }
  {
    IsoTpRecording rec(0xFFFF, 0, false);
    rec.message(profile, false);
    dir.write("multi_frame_profile", rec.bytes());
  }
  {
    IsoTpRecording rec(0xFFFF, 2, true);  // block size 2: the sender waits for FC every 2 CFs
    rec.message(profile, true);
    dir.write("block_size_2_padded", rec.bytes());
  }
  {
    IsoTpRecording rec(31, 0, false);  // at most 32 bytes: the profile's FF is refused
    rec.message(profile, false, 1);
    rec.message(status, false);
    dir.write("too_large_then_single", rec.bytes());
  }
  {
    IsoTpRecording rec(0xFFFF, 0, false);
    rec.message(profile, false, 3);  // FF and two CFs, then silence past N_Cr
    rec.timer(40);                  // 1600 ms
    rec.message(set_config, false);
    dir.write("timeout_then_message", rec.bytes());
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::fprintf(argc == 2 ? stdout : stderr, "usage: %s OUT_DIR\n", argv[0]);
    return argc == 2 ? 0 : 2;
  }
  try {
    const fs::path root(argv[1]);
    write_message_decoder(root);
    write_tcp_deframer(root);
    write_serial_deframer(root);
    write_isotp_reassembler(root);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "ldoem_fuzz_seed_writer: %s\n", error.what());
    return 1;
  }
  return 0;
}
