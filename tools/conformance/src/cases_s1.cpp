// s1/: what the public Ethernet driver (S1) does that the other groups do not: it switches a
// stream from range to range+echo with CANCEL_PROFILE and GET_PROFILE back to back, writes
// scan areas one SET_FUNCTION at a time and re-reads the whole table after each, builds tables
// whose measuring sector wraps through 0 deg, and relies on SET_CONFIG global committing the
// table (spec 3.3, 3.6). timing/TRANS_ROTATE_within_5_s_*: S1 gives up on a TRANS_ROTATE reply
// after 5 s (spec 6), at any speed it may ask for.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "case_steps.hpp"
#include "cases.hpp"

namespace ldoem::conformance {
namespace {

using namespace protocol;
using std::chrono::milliseconds;

constexpr std::uint16_t kHalfDegreeTicks = 8;
// Spec 3.3: TRANS_ROTATE takes 5..20 Hz (0 = the configured speed).
constexpr std::uint16_t kSlowestHz = 5;
constexpr std::uint16_t kFastestHz = 20;

// The table the device holds after restore_baseline(), all eight sectors (D4).
std::vector<SetFunction> baseline_table_all_sectors() {
  std::vector<SetFunction> table = baseline_sector_table();
  table.resize(kSectorCount);
  for (std::uint16_t sector = 0; sector < kSectorCount; ++sector) table[sector].sector = sector;
  return table;
}

// GET_FUNCTION for every sector, each compared with `table` (what was written is read back).
void expect_table(Session& session, std::string_view when, const std::vector<SetFunction>& table) {
  for (const SetFunction& sector : table) {
    session.expect(std::string(when) + ": GET_FUNCTION s" + std::to_string(sector.sector),
                   encode_request(GetFunction{sector.sector}),
                   session.pattern(reply_bytes(GetFunctionReply{sector.sector, sector.function, sector.stop_ticks}),
                                   {0, 1, 2, 3, 4, 5, 6, 7}));
  }
}

std::uint16_t format_of(ByteView profile) { return profile.size() >= 4 ? read_word_be(profile, 2) : 0; }

// S1 changes the profile format of a running stream by cancelling it and asking again at once,
// without waiting for the CANCEL_PROFILE reply in between. D10: no profile of the old stream
// after the reply; spec 3.5: the new stream has the new format; D3: PROFILESENT from 1 again.
void range_to_range_echo(Session& session) {
  // 0.5 deg: 540 points of 6 bytes fit the 5816 bytes TCP and serial carry (D3); 0.25 deg would not.
  session.set_global(1, 10, kHalfDegreeTicks);
  session.enter_rotate();
  session.enter_measure();
  start_profiles(session, 0, kFormatRange);
  session.send(encode_request(CancelProfile{}));
  session.send(encode_request(GetProfile{0, kFormatRangeEcho}));
  const Deadline deadline = Clock::now() + revolutions_wall(session, 3, 10) + session.options().reply_timeout;
  std::optional<Arrival> cancelled;
  while (!cancelled) {
    auto arrival = session.receive(deadline);
    if (!arrival) throw CaseFailed("no CANCEL_PROFILE reply after the switch request");
    const bool profile = arrival->payload.size() >= 2 && read_word_be(arrival->payload, 0) == 0x8301;  // spec 3.5
    if (!profile) {
      cancelled = std::move(arrival);
    } else if (format_of(arrival->payload) != kFormatRange) {
      throw CaseFailed("a profile of format " + std::to_string(format_of(arrival->payload)) +
                       " arrived before the CANCEL_PROFILE reply (the old stream is range, 0x39FF)");
    }
  }
  session.check("CANCEL_PROFILE reply", session.pattern(session.reply_vector("CANCEL_PROFILE, MEASURE")),
                cancelled->payload);
  ProfileExpectation expected;
  expected.format = kFormatRangeEcho;
  expected.sectors = expected_sectors(baseline_sector_table(), kHalfDegreeTicks);
  for (std::uint16_t sent = 1; sent <= 3; ++sent) {
    expected.profile_sent = session.emulator_target() ? std::optional<std::uint16_t>(sent) : std::nullopt;
    const std::string what = "range+echo profile " + std::to_string(sent) + " after the switch";
    const Arrival profile = session.await_profile(
        what, sent == 1 ? session.reply_wait_after(SimMilliseconds(400))
                        : revolutions_wall(session, 3, 10) + session.options().reply_timeout);
    check_profile(session, what, expected, profile.payload);
  }
  cancel_profiles(session);
}

// S1's scan areas [90, 270] and [315, 45] deg at 0.5 deg (spec 3.6), written one sector at a
// time, the whole table re-read after each write as S1 does; then SET_CONFIG global, and a
// profile whose third sector wraps through 0 deg.
void scan_areas_reread(Session& session) {
  std::vector<SetFunction> table = baseline_table_all_sectors();
  expect_table(session, "before", table);
  const std::vector<SetFunction> areas = {SetFunction{0, sector_function::kNormalMeasurement, 4320, 0},
                                          SetFunction{1, sector_function::kNoMeasurement, 5032, 0},
                                          SetFunction{2, sector_function::kNormalMeasurement, 720, 0},
                                          SetFunction{3, sector_function::kNoMeasurement, 1432, 0},
                                          SetFunction{4, sector_function::kNotInitialised, 0, 0}};
  for (const SetFunction& write : areas) {
    session.set_sector_table({write});
    table[write.sector] = write;
    expect_table(session, "after SET_FUNCTION s" + std::to_string(write.sector), table);
  }
  session.set_global(1, 10, kHalfDegreeTicks);
  expect_table(session, "after SET_CONFIG global", table);
  session.enter_rotate();
  session.enter_measure();
  ProfileExpectation expected;
  expected.format = kFormatRange;
  expected.profile_sent = session.emulator_target() ? std::optional<std::uint16_t>(1) : std::nullopt;
  expected.sectors = expected_sectors(table, kHalfDegreeTicks);  // s2: 5040 -> 720 through 0
  const Arrival profile = start_profiles(session, 1, kFormatRange);
  check_profile(session, "profile of the scan areas", expected, profile.payload);
}

std::string ms_text(double ms) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", ms);
  return text;
}

// A measuring sector from 180.25 deg through 0 to 90 deg, 270 deg wide: exactly the 10 800 Hz
// mean pulse limit at 10 Hz and 0.25 deg (spec 5), so TRANS_MEASURE must count its area across
// 0 deg (S1's own computation gets this wrong; spec 5). Its points run through 0 deg in order,
// and it is measured in one sweep: TEND - TSTART is its width over the head speed.
void sector_wrapping_through_zero(Session& session) {
  const std::vector<SetFunction> table = {SetFunction{0, sector_function::kNormalMeasurement, 1440, 0},
                                          SetFunction{1, sector_function::kNoMeasurement, 2880, 0},
                                          SetFunction{2, sector_function::kNotInitialised, 0, 0}};
  session.set_sector_table(table);
  session.set_global(1, 10, 4);
  session.enter_rotate();
  session.enter_measure();
  const std::uint16_t format = kFormatRange | profile_bits::kDirection;
  ProfileExpectation expected;
  expected.format = format;
  expected.sectors = expected_sectors(table, 4);  // s0: 2884 -> 1440, 1080 points
  session.send(encode_request(GetProfile{2, format}));
  for (std::uint16_t sent = 1; sent <= 2; ++sent) {
    expected.profile_sent = session.emulator_target() ? std::optional<std::uint16_t>(sent) : std::nullopt;
    const std::string what = "profile " + std::to_string(sent);
    const Arrival arrival = session.await_profile(what, session.reply_wait_after(SimMilliseconds(400)));
    const Profile profile = check_profile(session, what, expected, arrival.payload);
    const SectorBlock& wrapping = profile.sectors.at(0);
    const ExpectedSector& geometry = expected.sectors.at(0);
    std::uint16_t previous = wrapping.points.front().direction_ticks;
    for (std::size_t p = 1; p < wrapping.points.size(); ++p) {
      const std::uint16_t direction = wrapping.points[p].direction_ticks;
      const auto advance = static_cast<std::uint16_t>((direction + base::kTicksPerTurn - previous) % base::kTicksPerTurn);
      if (advance == 0 || advance > geometry.step_ticks * 2) {
        throw CaseFailed(what + ": point " + std::to_string(p) + " DIRECTION " + std::to_string(direction) + " after " +
                         std::to_string(previous) + ": the sector's points do not run through 0 deg in order");
      }
      if (session.emulator_target() && direction != (geometry.start_dir_ticks + p * geometry.step_ticks) % base::kTicksPerTurn) {
        throw CaseFailed(what + ": point " + std::to_string(p) + " DIRECTION " + std::to_string(direction) +
                         ", expected the nominal " +
                         std::to_string((geometry.start_dir_ticks + p * geometry.step_ticks) % base::kTicksPerTurn));
      }
      previous = direction;
    }
    const auto span_ms = static_cast<std::uint16_t>(wrapping.t_end_ms - wrapping.t_start_ms);
    const double width_ticks = (geometry.end_dir_ticks + base::kTicksPerTurn - geometry.start_dir_ticks) % base::kTicksPerTurn;
    const double sweep_ms = width_ticks / base::kTicksPerTurn * 100.0;  // 10 Hz
    // The emulator: the nominal sweep, +-1 ms of clock resolution; a device: within one revolution.
    const bool in_time = session.emulator_target() ? std::abs(span_ms - sweep_ms) <= 1.0 : span_ms <= 100;
    if (!in_time) {
      throw CaseFailed(what + ": TEND - TSTART of the wrapping sector is " + std::to_string(span_ms) + " ms; its " +
                       ms_text(width_ticks / base::kTicksPerDegree) + " deg take " + ms_text(sweep_ms) +
                       " ms at 10 Hz, in one sweep through 0 deg");
    }
  }
  session.expect_silence("after the 2 profiles of GET_PROFILE 2", revolutions_wall(session, 3, 10) + milliseconds(50));
}

// Spec 3.3: sectors sent with FLASHFLAG 0 become permanent when a SET_CONFIG global follows (S1
// sends one for that reason). DO_RESET 1 reloads the configuration from flash (D3).
void set_config_commits_table(Session& session) {
  const std::vector<SetFunction> committed = {SetFunction{0, sector_function::kNormalMeasurement, 2880, 0},
                                              SetFunction{1, sector_function::kNoMeasurement, 5040, 0},
                                              SetFunction{2, sector_function::kNormalMeasurement, 5200, 0},
                                              SetFunction{3, sector_function::kNotInitialised, 0, 0}};
  session.set_sector_table(committed);
  session.set_global(1, 10, 4);
  // A later temporary change that no SET_CONFIG commits.
  session.set_sector_table({SetFunction{2, sector_function::kNoMeasurement, 5600, 0}});
  const auto restart = [&session](std::string_view what) {
    session.expect(what, encode_request(DoReset{reset_level::kRestart}),
                   BytePattern::exactly(reply_bytes(DoResetReply{reset_level::kRestart})),
                   session.reply_wait_after(SimMilliseconds(10000)));
  };
  restart("DO_RESET 1");
  std::vector<SetFunction> expected = baseline_table_all_sectors();
  for (const SetFunction& sector : committed) expected[sector.sector] = sector;
  expect_table(session, "after DO_RESET 1 (flash)", expected);
  // And back: the baseline table committed again, as the suite promises to leave the device.
  session.restore_baseline();
  restart("DO_RESET 1 after the baseline");
  expect_table(session, "after the baseline and DO_RESET 1", baseline_table_all_sectors());
}

// Spec 6: S1 waits 5 s for the TRANS_ROTATE reply, which comes when the head is at speed (D7).
// From a stopped head, at every speed it may ask for, the reply must come within 5 s on the
// device's own clock: GET_SYNC_CLOCK right before and right after, minus the host's own time
// between (exact in --virtual-time; with a scaled clock the wire's latency is allowed for).
void rotate_within_five_seconds(Session& session) {
  constexpr double kLimitMs = 5000;
  constexpr double kWireSlackWallMs = 50;  // four one-way trips on a loaded host (scaled clock only)
  const bool virtual_time = session.options().virtual_time;
  const double scale = virtual_time ? 0.0 : session.options().time_scale;
  const double allowed_ms = kLimitMs + 1 + kWireSlackWallMs * scale;  // +1: the clock's 1 ms resolution
  std::ostringstream taken;
  for (std::uint16_t hz = kSlowestHz; hz <= kFastestHz; ++hz) {
    session.expect("DO_RESET 2 before " + std::to_string(hz) + " Hz", encode_request(DoReset{reset_level::kHaltToIdle}),
                   BytePattern::exactly(reply_bytes(DoResetReply{reset_level::kHaltToIdle})),
                   session.reply_wait_after(SimMilliseconds(10000)));
    // A real head coasts down after the reset; the emulator stops it in IDLE (D7).
    if (!session.emulator_target()) session.sleep_simulated(SimMilliseconds(5000));
    const Arrival before = session.request(encode_request(GetSyncClock{}));
    const Clock::time_point sent_at = Clock::now();
    const Arrival rotated = session.expect(
        "TRANS_ROTATE " + std::to_string(hz), encode_request(TransRotate{hz}),
        session.pattern(TransRotateReply{status(SensorMode::rotate)}, {0, 1, 5}), session.reply_wait_after(SimMilliseconds(10000)));
    const Clock::time_point asked_at = Clock::now();
    const Arrival after = session.request(encode_request(GetSyncClock{}));
    const double device_ms = static_cast<std::uint16_t>(clock_word(after.payload) - clock_word(before.payload));
    const double host_ms = std::chrono::duration<double, std::milli>((sent_at - before.at) + (asked_at - rotated.at)).count();
    const double spin_ms = device_ms - host_ms * scale;
    taken << (hz > kSlowestHz ? ", " : "") << hz << " Hz " << ms_text(spin_ms);
    if (spin_ms > allowed_ms) {
      throw CaseFailed("TRANS_ROTATE " + std::to_string(hz) + " Hz from a stopped head was answered after " +
                       ms_text(spin_ms) + " ms on the device clock; S1 gives up after 5000 ms (spec 6)" +
                       (virtual_time ? "" : "; allowed here " + ms_text(allowed_ms) + " ms") + " [" + taken.str() +
                       "]");
    }
  }
}

}  // namespace

void add_s1_cases(std::vector<Case>& cases) {
  cases.push_back(Case{"s1/CANCEL_PROFILE_then_GET_PROFILE_range_to_range_echo", range_to_range_echo, false, true, {}});
  cases.push_back(Case{"s1/scan_areas_table_reread_after_each_SET_FUNCTION", scan_areas_reread, false, true, {}});
  cases.push_back(Case{"s1/sector_wrapping_through_0_deg", sector_wrapping_through_zero, false, true, {}});
  // DO_RESET 1 is emulator-only (spec 8.9: whether a session survives it on the device is unknown).
  cases.push_back(Case{"s1/SET_CONFIG_global_commits_sector_table", set_config_commits_table, true, true, {}});
  cases.push_back(Case{"timing/TRANS_ROTATE_within_5_s_at_5_to_20_Hz", rotate_within_five_seconds, false, true, {}});
}

}  // namespace ldoem::conformance
