#include "profile_check.hpp"

#include "ldoem/protocol/text.hpp"

namespace ldoem::conformance {
namespace {

using namespace protocol;

std::uint16_t wrap_ticks(int ticks) {
  constexpr int kTicksPerTurn = static_cast<int>(base::kTicksPerTurn);
  const int wrapped = ((ticks % kTicksPerTurn) + kTicksPerTurn) % kTicksPerTurn;
  return static_cast<std::uint16_t>(wrapped);
}

// The expected profile with every unpredictable field taken from `received`, and the same with
// those fields inverted: bytes that differ between the two encodings are the holes.
struct ExpectedEncoding {
  Profile with_received_values;
  Profile with_inverted_values;
};

std::uint16_t inverted(std::uint16_t value) { return static_cast<std::uint16_t>(~value); }

ExpectedEncoding build(const ProfileExpectation& expected, const Profile& received) {
  ExpectedEncoding encoding;
  Profile& a = encoding.with_received_values;
  Profile& b = encoding.with_inverted_values;
  a.format = b.format = expected.format;
  a.profile_sent = expected.profile_sent.value_or(received.profile_sent);
  b.profile_sent = expected.profile_sent.value_or(inverted(received.profile_sent));
  a.profile_count = received.profile_count;
  b.profile_count = inverted(received.profile_count);
  a.layer = b.layer = 0;  // spec 3.5: always 0 on the LD
  for (std::size_t i = 0; i < expected.sectors.size(); ++i) {
    const ExpectedSector& sector = expected.sectors[i];
    const SectorBlock rx = i < received.sectors.size() ? received.sectors[i] : SectorBlock{};
    SectorBlock block_a;
    block_a.sector_num = sector.sector;
    block_a.t_start_ms = rx.t_start_ms;
    block_a.t_end_ms = rx.t_end_ms;
    SectorBlock block_b = block_a;
    block_b.t_start_ms = inverted(rx.t_start_ms);
    block_b.t_end_ms = inverted(rx.t_end_ms);
    if (sector.measuring) {
      block_a.dir_step_ticks = block_b.dir_step_ticks = sector.step_ticks;
      block_a.start_dir_ticks = block_b.start_dir_ticks = sector.start_dir_ticks;
      block_a.end_dir_ticks = block_b.end_dir_ticks = sector.end_dir_ticks;
      for (std::size_t p = 0; p < sector.points; ++p) {
        const ProfilePoint point = p < rx.points.size() ? rx.points[p] : ProfilePoint{};
        block_a.points.push_back(point);
        block_b.points.push_back(ProfilePoint{inverted(point.distance_q8_m), inverted(point.direction_ticks),
                                              inverted(point.echo)});
      }
    } else {
      // D3 fixes only POINTNUM 0 and no point fields for a non-measuring sector.
      block_a.dir_step_ticks = rx.dir_step_ticks;
      block_a.start_dir_ticks = rx.start_dir_ticks;
      block_a.end_dir_ticks = rx.end_dir_ticks;
      block_b.dir_step_ticks = inverted(rx.dir_step_ticks);
      block_b.start_dir_ticks = inverted(rx.start_dir_ticks);
      block_b.end_dir_ticks = inverted(rx.end_dir_ticks);
    }
    a.sectors.push_back(block_a);
    b.sectors.push_back(block_b);
  }
  a.status = b.status = make_status_block(expected.sensor, MotorMode::ok);  // D3: bytes 0..2 are 0
  return encoding;
}

}  // namespace

std::vector<ExpectedSector> expected_sectors(const std::vector<SetFunction>& table, std::uint16_t step_ticks) {
  std::vector<SetFunction> initialised;
  for (const SetFunction& sector : table) {
    if (sector.function == sector_function::kNotInitialised) break;
    initialised.push_back(sector);
  }
  std::vector<ExpectedSector> sectors;
  for (std::size_t i = 0; i < initialised.size(); ++i) {
    const SetFunction& sector = initialised[i];
    const SetFunction& previous = initialised[(i + initialised.size() - 1) % initialised.size()];
    ExpectedSector expected;
    expected.sector = sector.sector;
    expected.measuring = sector.function == sector_function::kNormalMeasurement ||
                         sector.function == sector_function::kReferenceMeasurement;
    expected.step_ticks = step_ticks;
    expected.start_dir_ticks = wrap_ticks(previous.stop_ticks + step_ticks);
    expected.end_dir_ticks = sector.stop_ticks;
    if (expected.measuring) {
      expected.points = wrap_ticks(sector.stop_ticks - expected.start_dir_ticks) / step_ticks + 1u;
    }
    sectors.push_back(expected);
  }
  return sectors;
}

std::vector<SetFunction> baseline_sector_table() {
  // D4: s0 normal measurement stop 2160 (135 deg), s1 no measurement stop 3600 (225 deg).
  return {SetFunction{0, sector_function::kNormalMeasurement, 2160, 0},
          SetFunction{1, sector_function::kNoMeasurement, 3600, 0}, SetFunction{2, 0, 0, 0}};
}

Profile check_profile(Session& session, std::string_view what, const ProfileExpectation& expected, ByteView received) {
  auto decoded = decode_profile(received);
  if (!session.emulator_target()) {
    // A device: code, format echo (S1 requires it), SENSTAT status byte MEASURE / motor OK.
    BytePattern pattern;
    pattern.bytes.assign(received.size(), std::nullopt);
    pattern.length_rule = LengthRule::at_least;
    Bytes head;
    append_word_be(head, 0x8301);
    append_word_be(head, expected.format);
    if (pattern.bytes.size() < 4) pattern.bytes.resize(4);
    for (std::size_t i = 0; i < 4; ++i) pattern.bytes[i] = head[i];
    if ((expected.format & profile_bits::kSensorStatus) != 0 && received.size() >= 8) {
      pattern.bytes.back() = StatusByte{expected.sensor, MotorMode::ok}.to_byte();
    }
    session.check(what, pattern, received);
    if (!decoded) throw CaseFailed(std::string(what) + ": profile does not decode: " + std::string(describe(decoded.error())));
    return *decoded;
  }
  if (!decoded) {
    throw CaseFailed(std::string(what) + ": profile does not decode: " + std::string(describe(decoded.error())),
                     "    received: " + format_hex(received.first(std::min<std::size_t>(received.size(), 48))) +
                         (received.size() > 48 ? " ..." : "") + "\n");
  }
  const ExpectedEncoding encoding = build(expected, *decoded);
  const Bytes a = encode_profile(encoding.with_received_values);
  const Bytes b = encode_profile(encoding.with_inverted_values);
  BytePattern pattern = BytePattern::exactly(a);
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (a[i] != b[i]) pattern.bytes[i] = std::nullopt;
  }
  session.check(what, pattern, received);
  return *decoded;
}

}  // namespace ldoem::conformance
